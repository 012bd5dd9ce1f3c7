// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/clock.hpp"

#include <chrono>
#include <ctime>

namespace mixload {
std::string utcNow() {
    const std::time_t t = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    char b[32];
    std::strftime(b, sizeof b, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&t));
    return b;
}
}  // namespace mixload
