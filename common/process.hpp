// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace mixload {

struct ProcessSpec {
    std::vector<std::string> argv;
    std::filesystem::path cwd;
    std::filesystem::path log;  // stdout and stderr, appended
    std::vector<std::pair<std::string, std::string>> env;  // added to the inherited environment
    std::function<void(const std::string&)> onLine;         // each output line, as it comes
    // When set, the child gets SIGTERM at this instant and runProcess throws DeadlineReached once
    // it has exited (mpirun passes the signal on to its ranks).
    std::optional<std::chrono::steady_clock::time_point> deadline;
};

class DeadlineReached : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Runs a child process to completion; returns its exit code (128 + signal if killed).
int runProcess(const ProcessSpec& spec);

// Last `n` lines of a text file, for error messages.
std::string tailLines(const std::filesystem::path& file, int n);

}  // namespace mixload
