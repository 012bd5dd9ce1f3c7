// SPDX-License-Identifier: GPL-3.0-or-later
// Command-line options that describe a collapse scene, shared by `collapse` and `bench collapse`.
#pragma once
#include <memory>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "scene/collapse_overrides.hpp"

namespace mixload::app {

struct CollapseOptions : scene::CollapseOverrides {
    void add(CLI::App* cmd);
};

}  // namespace mixload::app
