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

std::optional<std::chrono::steady_clock::time_point> deadlineAfterHours(double hours) {
    if (!(hours > 0)) return std::nullopt;
    return std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                  std::chrono::duration<double>(hours * 3600.0));
}
}  // namespace mixload
