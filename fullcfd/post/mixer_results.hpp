// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/mixer_scene.hpp"

namespace mixload::post {

struct LoadingSample {
    double t, loading, inflow, outflow, fed, out, maxPowderSpeed;
    double zoneLoading;  // powder in the rotor cellZone [kg]; NaN in histories from before it
    double denseLoading;  // powder in cells more than half powder [kg]; NaN likewise
};

// The loading monitor's per-step history, merged across restarts.
std::vector<LoadingSample> readLoadingHistory(const std::filesystem::path& caseDir);

// The monitor's steady verdict (postProcessing/loading/steady), if the run reached one.
std::optional<nlohmann::json> readSteadyVerdict(const std::filesystem::path& caseDir);

// Mesh facts from checkMesh's log: cells, max non-orthogonality, max skewness, "ok".
nlohmann::json readCheckMesh(const std::filesystem::path& caseDir);

// The result record of a mixer run (without timings).
nlohmann::json mixerResult(const scene::MixerScene& s, const std::filesystem::path& caseDir);

// Where a mixer result's own simulation started [s]: start_time_s, or for results written before
// it was recorded the first time of their history, else 0. Costs per simulated second divide by
// end_time_s minus this, so a run that continued another's time is charged only its own seconds.
double startTime(const nlohmann::json& result);

// Adds a warning to a result: warnings accumulate in one "warning" string, separated by "; ".
void addWarning(nlohmann::json& result, const std::string& warning);

// Writes loading.png (M(t), and the outflow beside the feed) into caseDir; returns a warning or "".
std::string plotLoading(const scene::MixerScene& s, const std::filesystem::path& caseDir);

}  // namespace mixload::post
