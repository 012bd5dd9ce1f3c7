// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>

#include <nlohmann/json.hpp>

#include "scene/mixer_scene.hpp"

namespace mixload::run {

struct MixerJob {
    scene::MixerScene scene;
    int np = 1;
    std::filesystem::path out;  // empty: runs/mixer-<hash>[-np<N>]
    bool progress = false;
    bool reuse = true;          // return a finished run's result instead of running again
};

// Meshes, runs (or resumes, or reuses) a mixer run and returns its result record, also written to
// <run dir>/result.json. The scene is validated before anything is created.
nlohmann::json runMixer(const MixerJob& job);

std::filesystem::path defaultMixerDir(const scene::MixerScene& s, int np);

}  // namespace mixload::run
