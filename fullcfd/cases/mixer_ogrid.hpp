// SPDX-License-Identifier: GPL-3.0-or-later
// The mixer's O-grid: a blockMesh mesh whose rotating zone is bounded by exact block faces (a
// cylinder in the middle of the tip gap, short of both end faces), with the paddles cut out of the
// zone as stair-stepped cells (topoSet + subsetMesh). For the sliding mesh (sm) the zone's faces
// are an AMI interface; for the frozen rotor (mrf, lts) the mesh is conformal and the zone reaches
// the paddle tips, so no powder rests in cells that the rotor frame leaves out. No
// snappyHexMesh: block faces give an exact, repeatable zone and an outlet/weir split on block edges.
#pragma once
#include <string>
#include <vector>

#include "scene/mixer_scene.hpp"

namespace mixload::cases {

// Sizes of the O-grid for a scene (cell counts per block direction).
struct OGridSize {
    int sectors = 8;        // angular blocks; sector edges 0 and sectors/2 lie on the weir chord
    int perSector = 0;      // cells per sector around
    int radialInner = 0;    // shaft -> paddle tips
    int radialTip = 1;      // paddle tips -> interface
    int radialOuter = 1;    // interface -> bore
    int axialEnd = 1;       // each stationary end layer
    int axialMid = 0;       // the rotating zone's length
    double paddleThickness = 0;  // thickness of the cut-out paddles [m] (>= the scene's; cases/meshed_geometry refuses more than 2% over)
    long cells() const;     // before the paddles are cut out
};

OGridSize ogridSize(const scene::MixerScene& s);
// The thinnest paddle the O-grid of this scene's cell size closes to flow [m].
double ogridMinPaddleThickness(const scene::MixerScene& s);
double ogridMinPaddleThickness(const scene::MixerScene& s, const OGridSize& c);

std::string ogridBlockMeshDict(const scene::MixerScene& s);
// The paddle cells (cut out) and the cells kept.
std::string ogridTopoSetDict(const scene::MixerScene& s);
// The inlet port's faces on the feed end face (system/topoSetDict.inlet).
std::string ogridInletTopoSetDict(const scene::MixerScene& s);
std::string ogridCreatePatchDict();

std::vector<std::vector<std::string>> ogridMeshSteps();

}  // namespace mixload::cases
