// SPDX-License-Identifier: GPL-3.0-or-later
// Each subcommand registers itself on the CLI11 app and sets the action run after parsing.
#pragma once
#include <functional>

#include <CLI/CLI.hpp>

namespace mixload::app {
using Action = std::function<int()>;
void addInfo(CLI::App& app, Action& action);
void addCollapse(CLI::App& app, Action& action);
void addBench(CLI::App& app, Action& action);
void addStudy(CLI::App& app, Action& action);
void addCampaign(CLI::App& app, Action& action);
void addMixer(CLI::App& app, Action& action);
void addSnapshots(CLI::App& app, Action& action);
void addSurrogate(CLI::App& app, Action& action);  // also `check`
void addPredict(CLI::App& app, Action& action);    // also `whatif`
}  // namespace mixload::app
