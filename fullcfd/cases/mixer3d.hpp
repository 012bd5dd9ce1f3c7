// SPDX-License-Identifier: GPL-3.0-or-later
// The 3D continuous mixer as an interFoam case. Mesh: a blockMesh O-grid (mixer_ogrid) whose rotor
// zone is a frozen-rotor cellZone (mrf, lts) or turns as a sliding mesh behind an AMI (sm); or,
// for mrf/lts only, the older castellated blockMesh + snappyHexMesh mesh (scene mesher = snappy).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "scene/mixer_scene.hpp"

namespace mixload::cases {

inline constexpr const char* kLoadingMonitor = "loading";
inline constexpr const char* kCourantProfile = "courant";

// Writes surfaces, the meshing dictionaries (blockMesh, snappyHexMesh or createPatch, topoSet) and
// the system dictionaries the utilities and the solver share (controlDict, fvSchemes, fvSolution,
// decomposeParDict).
void writeMixerMeshCase(const scene::MixerScene& s, const std::filesystem::path& caseDir, int np);

// (Re)writes system/controlDict; keepAllTimes keeps every written time (for snapshots) instead of
// the last three; profile turns on OpenFOAM's profiler and the Courant probe (post/run_profile).
// The solver rereads it, so a resumed run can switch. A run that continues another at its time
// (timeOffset, s) counts its end-time cap and its min-time from there.
void writeMixerControlDict(const scene::MixerScene& s, const std::filesystem::path& caseDir,
                           bool keepAllTimes, bool profile, double timeOffset = 0);

// The utilities that turn the written case into the final mesh, in order.
std::vector<std::vector<std::string>> mixerMeshSteps(const scene::MixerScene& s);

// Writes constant/ (transport, gravity, MRF or mesh motion), the 0/ fields (after meshing, so
// fields see the final patches) and setFieldsDict for the initial deposit.
void writeMixerSolverCase(const scene::MixerScene& s, const std::filesystem::path& caseDir);

// Height of the initial deposit surface (z) for the scene's initial loading.
double initialBedHeight(const scene::MixerScene& s);

}  // namespace mixload::cases
