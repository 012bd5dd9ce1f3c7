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

// Bad input to `mixload <subcommand> args --out DIR`: exit code 2, one line on stderr that contains
// needle, and neither DIR nor DIR.tmp left behind.
void expectRejected(const std::string& subcommand, std::vector<std::string> args,
                    const std::string& needle);

}  // namespace mixload::testing
