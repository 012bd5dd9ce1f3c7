// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/mixer_scene.hpp"

namespace mixload::experiments {

// A sweep of mixer runs (methods x meshes x rpm x feed). Runs live in <runs>/<scene hash>, so an
// interrupted study resumes each run from its last written time and never repeats a finished one,
// and studies that share a run store share their common points.
struct MixerStudy {
    std::vector<scene::MixerScene> scenes;
    std::filesystem::path out;
    std::filesystem::path runs;  // empty: <out>/runs
    int jobs = 1;
    int np = 1;  // MPI ranks per run
    bool progress = false;
    // Each sliding-mesh run starts from the latest fields of the study's MRF run at the same point
    // (run first), instead of its deposit: the two differ by some 15% (the paper), while the 0.316 kg
    // deposit is 2.6 times MRF's 0.12 kg at 162 rpm and 45 kg/h (2 cm).
    bool smFromMrf = false;
    // With smFromMrf: only the highest feed's sm run at each speed starts from MRF; each lower feed
    // continues the sm run at the next higher one, at its time and angle (a bed drains faster than
    // a low feed fills one).
    bool smDownFeeds = false;
    // --max-hours: runs still going here stop, keeping what they ran; the next call of the same
    // study resumes them in their directories (rows {"stopped": why}, not errors).
    std::optional<std::chrono::steady_clock::time_point> deadline;
};

// Runs (or resumes, or reuses) each scene in <runs>/<scene hash> on `jobs` threads and returns what
// a study keeps of each result (loading, steady verdict, balance, costs, run_dir, history), or
// {"error": ...} for a run that failed. warmFrom is empty (every run from its deposit) or holds one
// entry per scene: a run directory whose latest fields start that run (empty entry: the deposit),
// in <runs>/<scene hash>-warm-<source tag>, so that cold and warm runs never share a directory.
// A run that the deadline (or SIGTERM under stopOnSignals) stops, or that it keeps from starting,
// gives {"stopped": why}.
std::vector<nlohmann::json> runMixerScenes(const std::vector<scene::MixerScene>& scenes,
                                           const std::filesystem::path& runs, int jobs, int np, bool progress,
                                           const std::string& label,
                                           const std::vector<std::filesystem::path>& warmFrom = {},
                                           std::optional<std::chrono::steady_clock::time_point> deadline = std::nullopt);

// Runs the study and writes <out>/table.csv, <out>/table.md and <out>/study.png (M against feed
// and against rpm). Returns the rows.
nlohmann::json runMixerStudy(const MixerStudy& study);

}  // namespace mixload::experiments
