// SPDX-License-Identifier: GPL-3.0-or-later
// Command-line options that describe a collapse scene, shared by `collapse` and `bench collapse`.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "scene/collapse_scene.hpp"

namespace mixload::app {

struct CollapseOptions {
    std::string material = "quartz";
    double aspect = 2.0;
    double length = 0.05;
    int cellsPerLength = 30;
    std::optional<double> muS, muD, I0, etaMax;
    std::string rheology = "muI";
    std::string convention = "standard";
    double restFraction = 0.01;
    double capTstar = 15.0;

    void add(CLI::App* cmd);
    // Loads the material, applies overrides, validates: throws InputError before anything is written.
    scene::CollapseScene scene() const;
};

}  // namespace mixload::app
