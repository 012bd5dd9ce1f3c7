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

namespace mixload::testing {
// Test scenes whose paddles the CI's coarse meshes can cut (tests/data/scenes): the shipped scenes'
// paddles need finer cells, and their runs refuse on these meshes.
inline const std::string kGcm250At1cm = MIXLOAD_TEST_DATA "/scenes/gcm250-1cm.toml";
inline const std::string kGcm250At2cm = MIXLOAD_TEST_DATA "/scenes/gcm250-2cm.toml";
inline const std::string kV3At2cm = MIXLOAD_TEST_DATA "/scenes/v3-2cm.toml";
// A 1 mm feed port on 1 cm cells: the mesh has no inlet face.
inline const std::string kPinholeInlet1cm = MIXLOAD_TEST_DATA "/scenes/gcm250-1cm-pinhole.toml";
}  // namespace mixload::testing
