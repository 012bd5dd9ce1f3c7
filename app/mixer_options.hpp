// SPDX-License-Identifier: GPL-3.0-or-later
// Command-line options that describe a mixer run, shared by `mixer` and `bench mixer`.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "scene/mixer_overrides.hpp"

namespace mixload::app {

struct MixerOptions : scene::MixerOverrides {
    void add(CLI::App* cmd, bool withMethod = true);
};

}  // namespace mixload::app
