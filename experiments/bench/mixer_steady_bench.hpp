// SPDX-License-Identifier: GPL-3.0-or-later
// The cost of a steady mixer loading: the same operating points run to their steady verdict with
// a baseline setup (legacy numerics, window verdict, cold start from the deposit) and with the
// current one, cold and warm, in one process, with the answer beside the time.
#pragma once
#include <filesystem>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/mixer_scene.hpp"

namespace mixload::experiments {

struct SteadyBench {
    scene::MixerScene scene;                       // the current setup; points override rpm, feed
    std::vector<std::pair<double, double>> points;  // (rpm, feed kg/h)
    bool baseline = true;  // also run legacy numerics + window verdict, cold
    bool warm = true;      // also run each point warm, from the previous point's current-setup run
    int np = 1;
    std::filesystem::path out;  // scratch: replaced
    bool progress = false;
};

// Runs every point and setup (baseline first, so that it meets the same machine state) and
// returns {"runs": [...], "summary": {...}}; each run row holds wall time to the verdict, steps,
// Courant numbers, loading, its difference from the baseline's, and the powder leak.
nlohmann::json runSteadyBench(const SteadyBench& bench);

// The table a terminal shows.
std::string formatSteadyBench(const nlohmann::json& result);

}  // namespace mixload::experiments
