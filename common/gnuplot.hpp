// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
#include <optional>
#include <string>

namespace mixload {
// Runs a gnuplot script (which sets its own PNG output) in dir. Plots are a convenience: failure
// is reported as a warning string (empty on success), never as a failed run.
std::string runGnuplot(const std::filesystem::path& dir, const std::string& scriptName,
                       const std::string& script);
// Renders dir/<name>.png from `body` (the script after its terminal and output lines), written to
// a temporary name and renamed, so a plot cut short never carries the final name; the script is
// kept as <name>.gp. Returns the PNG's path, or nothing and the reason in `warning`.
std::optional<std::filesystem::path> renderPng(const std::filesystem::path& dir, const std::string& name, const std::string& terminal,
                                               const std::string& body, std::string& warning);
}  // namespace mixload
