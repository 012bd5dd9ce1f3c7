// SPDX-License-Identifier: GPL-3.0-or-later
// Command-line options that describe a mixer run, shared by `mixer` and `bench mixer`.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "scene/mixer_scene.hpp"

namespace mixload::app {

struct MixerOptions {
    std::string scene = scene::kDefaultMixerScene;
    std::optional<std::string> method, mesh, mesher, rheology, convention, numerics;
    std::optional<double> rpm, feedKgH, muS, muD, I0, d, rho, initialLoadingKg, endTime, cellSize,
        etaMax, window, residence, tol, flowTol, minTime, airViscosity, courantAlphaMin, maxDeltaT;
    std::optional<int> ltsIterations, nonOrthCorrectors, alphaSubCycles;
    std::vector<std::string> sets;  // --set TABLE.KEY=VALUE, applied to the scene file

    void add(CLI::App* cmd, bool withMethod = true);
    // Loads the scene file, applies the flags, validates: throws InputError before anything is
    // written.
    // `keys` are set on top of --set (a calibration's parameters).
    scene::MixerScene build(const scene::SceneKeys& keys = {}) const;
};

}  // namespace mixload::app
