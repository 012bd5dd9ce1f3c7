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
    // Whether a stop asked for by a signal (stopOnSignals) ends this child too. A solver's run is
    // stopped; the short tools a stopping driver still runs to leave its work whole (mesh and
    // reconstruct utilities, gnuplot for the report of what it ran) are not: killed, they turned a
    // clean stop into an error and a report never written.
    bool stopOnRequest = true;
};

class DeadlineReached : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// A run its deadline (or a stop request) kept from starting: nothing of it ran this time.
class NotStarted : public DeadlineReached {
public:
    using DeadlineReached::DeadlineReached;
};

// From this call on, SIGTERM and SIGINT (Ctrl-C) ask for a stop instead of killing the process: the
// child running under runProcess gets SIGTERM and runProcess throws DeadlineReached, as at a
// deadline, so a campaign driver stops the way --max-hours stops it (points released, progress kept).
void stopOnSignals();
bool stopRequested();
// Whether work under this deadline should not begin: a stop was asked for, or the deadline passed.
bool timeIsUp(const std::optional<std::chrono::steady_clock::time_point>& deadline);

// Runs a child process to completion; returns its exit code (128 + signal if killed).
int runProcess(const ProcessSpec& spec);

// Last `n` lines of a text file, for error messages.
std::string tailLines(const std::filesystem::path& file, int n);

}  // namespace mixload
