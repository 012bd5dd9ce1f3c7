// SPDX-License-Identifier: GPL-3.0-or-later
#include "cli_harness.hpp"

#include <unistd.h>

#include <algorithm>

#include <gtest/gtest.h>

#include "common/atomic_file.hpp"
#include "common/process.hpp"

namespace mixload::testing {

namespace fs = std::filesystem;

fs::path scratchDir(const std::string& name) {
    const fs::path d = fs::temp_directory_path() / ("mixload-test-" + std::to_string(::getpid())) / name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
}

CliResult runMixload(const std::vector<std::string>& args) {
    const fs::path err = scratchDir("stderr") / "err.txt";
    std::string cmd = "exec \"$0\"";
    for (size_t i = 0; i < args.size(); ++i) cmd += " \"${" + std::to_string(i + 1) + "}\"";
    cmd += " 2>" + err.string();
    ProcessSpec spec;
    spec.argv = {"sh", "-c", cmd, MIXLOAD_EXE};
    spec.argv.insert(spec.argv.end(), args.begin(), args.end());
    CliResult r;
    spec.onLine = [&](const std::string& l) { r.out += l + "\n"; };
    r.rc = runProcess(spec);
    r.err = readFile(err);
    return r;
}

void expectRejected(const std::string& subcommand, std::vector<std::string> args,
                    const std::string& needle) {
    const fs::path out = scratchDir("bad-input-" + subcommand) / "run";
    args.insert(args.begin(), subcommand);
    args.push_back("--out");
    args.push_back(out.string());
    const auto r = runMixload(args);
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find(needle), std::string::npos) << "stderr: " << r.err;
    EXPECT_FALSE(fs::exists(out)) << "a run directory was left behind";
    EXPECT_FALSE(fs::exists(out.string() + ".tmp"));
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

}  // namespace mixload::testing
