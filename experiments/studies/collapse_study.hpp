// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/collapse_scene.hpp"

namespace mixload::experiments {

// A sweep of collapse runs: every combination of material x rheology x aspect x mesh. Runs live in
// <out>/runs/<scene hash>, so an interrupted study resumes where it stopped and finished runs are
// never repeated.
struct CollapseStudy {
    std::vector<scene::CollapseScene> scenes;
    std::filesystem::path out;
    int jobs = 1;
    bool progress = false;
};

// Runs the study and writes <out>/table.csv, <out>/table.md and <out>/study.png. Returns the rows.
nlohmann::json runCollapseStudy(const CollapseStudy& study);

}  // namespace mixload::experiments
