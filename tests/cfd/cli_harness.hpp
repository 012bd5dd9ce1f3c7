// SPDX-License-Identifier: GPL-3.0-or-later
// Runs the real mixload executable (built alongside the tests) and captures what it prints.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace mixload::testing {

struct CliResult {
    int rc = -1;
    std::string out;
    std::string err;
};

CliResult runMixload(const std::vector<std::string>& args);

// A fresh scratch directory for one test (removed first if it exists).
std::filesystem::path scratchDir(const std::string& name);

}  // namespace mixload::testing
