// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "scene/collapse_scene.hpp"

namespace mixload::run {

struct CollapseJob {
    scene::CollapseScene scene;
    int np = 1;
    std::filesystem::path out;  // empty: runs/collapse-<hash>[-np<N>]
    bool progress = false;
    bool reuse = true;          // return a finished run's result instead of running again
    bool snapshots = false;     // export <run dir>/snapshots.h5 at the end
    // Campaigns stop long runs here; they resume later from their last written time. Past it a run
    // does not start (NotStarted), though a finished one is still returned.
    std::optional<std::chrono::steady_clock::time_point> deadline;
};

// Runs (or resumes, or reuses) a collapse and returns its result record, which is also written to
// <run dir>/result.json. The scene must be valid; nothing is created before that is checked.
nlohmann::json runCollapse(const CollapseJob& job);

std::filesystem::path defaultCollapseDir(const scene::CollapseScene& s, int np);

}  // namespace mixload::run
