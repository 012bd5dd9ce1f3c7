// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload stress`: a sweep that tries to break the solver and the tools. Every case runs the real
// mixload executable as a child process (real runs, real files) and ends in one of:
//   result        exit 0 and the result's own checks pass (powder conserved, values physical)
//   clear-error   exit 1 or 2 with one message on stderr that says what was wrong
//   skipped       the case cannot be staged on this machine (said why)
//   silent-failure anything else: a crash, an exit without a message, a result that fails its own
//                  checks while reporting success, a half-written result left behind
// A silent failure is a bug to fix; the command exits 1 when there is one.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mixload::experiments {

struct StressOutcome {
    int rc = -1;
    std::string out, err;
    double seconds = 0;
};

struct StressStep {
    std::vector<std::string> args;  // mixload arguments; {dir} is the case's directory, {data} the data dir
    double killAfterSeconds = 0;    // > 0: SIGKILL the step after this long (a crash mid-run)
    bool background = false;        // runs beside the next step, killed once that one ends
};

struct StressCase {
    std::string group, name, tries;
    bool quick = true;  // in the CI tier
    std::vector<StressStep> steps;  // the last step is judged
    // Before the steps: prepares files; returns "" or why the case cannot be staged (skipped).
    std::function<std::string(const std::filesystem::path& dir)> setup;
    // Between the steps: damage a file the previous step wrote (corrupt, truncate); returns "" or a
    // reason to skip.
    std::function<std::string(const std::filesystem::path& dir, size_t step)> between;
    // The result's own checks for exit 0: "" when they pass, else what failed.
    std::function<std::string(const StressOutcome&, const std::filesystem::path& dir)> check;
    // Cleans up after the case (unmounts).
    std::function<void(const std::filesystem::path& dir)> teardown;
};

std::vector<StressCase> stressCases();

struct StressOptions {
    std::filesystem::path out = "runs/stress";
    std::filesystem::path exe;      // the mixload executable
    bool full = false;              // the full tier (tiny mixer runs) beside the quick one
    std::vector<std::string> only;  // groups; empty: all
    bool progress = false;
};

// Runs the cases; writes <out>/stress.md, stress.csv, stress.json; returns the report (counts and
// rows).
nlohmann::json runStress(const StressOptions& o);

// How an outcome is classed, given the case's check: result | clear-error | silent-failure, and why.
std::pair<std::string, std::string> classifyStress(const StressOutcome& o, const std::string& checkFailure);

}  // namespace mixload::experiments
