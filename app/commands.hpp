// SPDX-License-Identifier: GPL-3.0-or-later
// Each subcommand registers itself on the CLI11 app and sets the action run after parsing.
#pragma once
#include <functional>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

namespace mixload::app {
using Action = std::function<int()>;
void addInfo(CLI::App& app, Action& action);
void addCollapse(CLI::App& app, Action& action);
void addBench(CLI::App& app, Action& action);
void addBenchPredict(CLI::App* bench, Action& action);
void addBenchRom(CLI::App* bench, Action& action);
void addBenchParetoMixer(CLI::App* bench, Action& action);
void addStudy(CLI::App& app, Action& action);
void addCampaign(CLI::App& app, Action& action);
void addCalibrate(CLI::App& app, Action& action);
void addMixer(CLI::App& app, Action& action);
void addSnapshots(CLI::App& app, Action& action);
void addSurrogate(CLI::App& app, Action& action);  // also `check`
void addPredict(CLI::App& app, Action& action);    // also `whatif`
void addRom(CLI::App& app, Action& action);
void addSensitivity(CLI::App& app, Action& action);
void addPlane(CLI::App& app, Action& action);
void addStress(CLI::App& app, Action& action);

// `mixload check`: compares the model with the runs of a campaign (or table, or the model's own
// campaign when both are empty), records the result in the model unless !record; 1 when the mean
// hold-out error exceeds threshold. listRuns adds a table of every run, worst first; a plotDir gets
// the parity plot (parity.png).
int runCheck(const std::string& modelPath, const std::string& campaign, const std::string& dir,
             const std::string& table, std::optional<double> threshold, bool record, bool json,
             bool quiet = false, bool listRuns = false, const std::string& plotDir = "");
}  // namespace mixload::app
