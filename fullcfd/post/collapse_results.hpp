// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/collapse_scene.hpp"

namespace mixload::post {

struct CollapseSample {
    double t, volume, kineticEnergy, front, height;
};

// The monitor's per-step history, merged across restarts (a later segment replaces the tail of
// an earlier one from its start time on).
std::vector<CollapseSample> readCollapseHistory(const std::filesystem::path& caseDir);

// Final deposit profile h(x): pairs (x, h) from the monitor's latest profile file.
std::vector<std::pair<double, double>> readFinalProfile(const std::filesystem::path& caseDir);

bool collapseReachedRest(const std::filesystem::path& caseDir);

// The result record of a finished collapse run (without timings).
nlohmann::json collapseResult(const scene::CollapseScene& s, const std::filesystem::path& caseDir);

// Writes collapse.png (L*(t/t*) and the final deposit) into caseDir; returns a warning or "".
std::string plotCollapse(const scene::CollapseScene& s, const std::filesystem::path& caseDir);

}  // namespace mixload::post
