// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
#include <string>

namespace mixload {
// Runs a gnuplot script (which sets its own PNG output) in dir. Plots are a convenience: failure
// is reported as a warning string (empty on success), never as a failed run.
std::string runGnuplot(const std::filesystem::path& dir, const std::string& scriptName,
                       const std::string& script);
}  // namespace mixload
