// SPDX-License-Identifier: GPL-3.0-or-later
// A mixer run described as a scene file plus overrides (what `mixer`, studies, campaigns and
// calibrations are given): every unset value comes from the scene file.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "scene/mixer_scene.hpp"

namespace mixload::scene {

struct MixerOverrides {
    std::string scene = kDefaultMixerScene;
    std::optional<std::string> method, mesh, mesher, rheology, convention, numerics;
    std::optional<double> rpm, feedKgH, muS, muD, I0, d, rho, initialLoadingKg, endTime, cellSize,
        etaMax, window, residence, tol, flowTol, minTime, airViscosity, courantAlphaMin, maxDeltaT,
        maxCourant;
    std::optional<int> ltsIterations, nonOrthCorrectors, alphaSubCycles;
    std::vector<std::string> sets;  // TABLE.KEY=VALUE, applied to the scene file

    // Loads the scene file, applies the overrides, validates: throws InputError before anything is
    // written. `keys` are set on top of `sets` (a calibration's parameters).
    MixerScene build(const SceneKeys& keys = {}) const;
};

}  // namespace mixload::scene
