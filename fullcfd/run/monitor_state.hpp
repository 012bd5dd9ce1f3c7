// SPDX-License-Identifier: GPL-3.0-or-later
// The loading monitor's steady-test history outlives a lost run directory. Kept beside a campaign
// point's latest fields (experiments/campaign/progress), it seeds the run that continues them, so
// that the history the verdict needs (two windows of at least half a residence time each: at a
// slow point 200 s of flow, two hours of wall time on 1 cm) is not run again.
#pragma once
#include <cstddef>
#include <filesystem>

#include <nlohmann/json.hpp>

namespace mixload::run {

// The monitor's state at a written time directory of a mixer run: {time_s, fed_kg, out_kg,
// t, loading_kg, out_cumulative_kg}, its samples thinned evenly to at most maxSamples (the last
// kept; the test reads time-weighted window means of them). Null when the time holds none.
nlohmann::json keptMonitorState(const std::filesystem::path& timeDir, std::size_t maxSamples = 1000);

// Writes a kept state into <case>/0 for a run that continues it from its own time 0: samples
// shifted to end at 0 s and 0 kg out, the cumulative sums restarted (the run's powder balance is
// its own). Returns the span of history given [s]. Throws on a state of another shape.
double seedMonitorState(const std::filesystem::path& caseDir, const nlohmann::json& kept);

}  // namespace mixload::run
