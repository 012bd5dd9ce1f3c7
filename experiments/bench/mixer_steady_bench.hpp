// SPDX-License-Identifier: GPL-3.0-or-later
// The cost of a steady mixer loading: the same operating points run to their steady verdict with
// the baseline setup (legacy numerics, cold start from the deposit) and with the current one, cold
// and warm, in one process, with the answer beside the time.
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
    bool baseline = true;  // also run legacy numerics, cold
    // Also run each point warm: from the same point's baseline run when there is one (the cost of
    // a verdict from a converged field, e.g. a campaign rerun with new numerics), else from the
    // previous point's cold run.
    bool warm = true;
    bool resume = false;  // reuse finished runs in out instead of replacing it
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
