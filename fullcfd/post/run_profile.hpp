// SPDX-License-Identifier: GPL-3.0-or-later
// Where a run's time steps and its wall time went: the time step and what limited it, where the
// largest Courant numbers sit (region of the mixer and phase), the time per step split by stage
// of the solver, and the iterations of each linear solve. Read from the solver's log, the
// courantProfile probe and OpenFOAM's profiler, which a run writes when asked (`--profile`).
#pragma once
#include <filesystem>

#include <nlohmann/json.hpp>

namespace mixload::post {

// Needs log.interFoam; the Courant locations need postProcessing/courant, the stage split
// <latest time>/uniform/profiling (both absent unless the run was profiled: those keys are then null).
nlohmann::json readRunProfile(const std::filesystem::path& caseDir);

// The profile as a few lines of text for a terminal.
std::string formatRunProfile(const nlohmann::json& profile);

}  // namespace mixload::post
