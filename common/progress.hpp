// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <string>

namespace mixload {

// One-line progress with percentage and ETA on stderr. Silent unless enabled and stderr is a
// terminal, so --json output and logs stay clean.
class Progress {
public:
    Progress(std::string label, bool enabled);
    void update(double fraction, const std::string& detail = "");
    void finish();

private:
    std::string label_;
    bool enabled_;
    std::chrono::steady_clock::time_point start_;
    std::chrono::steady_clock::time_point lastDraw_;
};

}  // namespace mixload
