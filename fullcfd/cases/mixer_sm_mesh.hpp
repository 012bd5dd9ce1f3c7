// SPDX-License-Identifier: GPL-3.0-or-later
// The sliding-mesh (sm) mixer mesh: a blockMesh O-grid whose rotating zone is bounded by exact
// block faces, so its AMI interface is the same cylinder on both sides, and paddles cut out of the
// zone as stair-stepped cells (topoSet + subsetMesh). No snappyHexMesh: block faces give an exact,
// repeatable interface and an outlet/weir split on block edges.
#pragma once
#include <string>
#include <vector>

#include "scene/mixer_scene.hpp"

namespace mixload::cases {

// Sizes of the O-grid for a scene (cell counts per block direction).
struct SmGrid {
    int sectors = 8;        // angular blocks; sector edges 0 and sectors/2 lie on the weir chord
    int perSector = 0;      // cells per sector around
    int radialInner = 0;    // shaft -> paddle tips
    int radialTip = 1;      // paddle tips -> interface
    int radialOuter = 1;    // interface -> bore
    int axialEnd = 1;       // each stationary end layer
    int axialMid = 0;       // the rotating zone's length
    double paddleThickness = 0;  // thickness of the cut-out paddles [m] (>= the scene's)
    long cells() const;     // before the paddles are cut out
};

SmGrid smGrid(const scene::MixerScene& s);

std::string smBlockMeshDict(const scene::MixerScene& s);
// The paddle cells (cut out) and the cells kept.
std::string smTopoSetDict(const scene::MixerScene& s);
// The inlet port's faces on the feed end face (system/topoSetDict.inlet).
std::string smInletTopoSetDict(const scene::MixerScene& s);
std::string smCreatePatchDict();

std::vector<std::vector<std::string>> smMeshSteps();

}  // namespace mixload::cases
