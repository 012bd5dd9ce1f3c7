// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
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
};

// Runs the study and writes <out>/table.csv, <out>/table.md and <out>/study.png (M against feed
// and against rpm). Returns the rows.
nlohmann::json runMixerStudy(const MixerStudy& study);

}  // namespace mixload::experiments
