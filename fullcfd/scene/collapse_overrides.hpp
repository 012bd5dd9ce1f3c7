// SPDX-License-Identifier: GPL-3.0-or-later
// A collapse described as a material plus overrides (what `collapse`, studies and campaigns are given).
#pragma once
#include <optional>
#include <string>

#include "scene/collapse_scene.hpp"

namespace mixload::scene {

struct CollapseOverrides {
    std::string material = "quartz";
    double aspect = 2.0;
    double length = 0.05;
    int cellsPerLength = 30;
    std::optional<double> muS, muD, I0, etaMax;
    double capHeightRatio = 1.0;
    double maxCourant = 0.3;
    std::string rheology = "muI";
    std::string convention = "standard";
    double restFraction = 0.01;
    double capTstar = 15.0;
    int writesPerTstar = 4;

    // Loads the material, applies overrides, validates: throws InputError before anything is written.
    CollapseScene scene() const;
};

}  // namespace mixload::scene
