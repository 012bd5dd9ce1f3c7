// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <optional>
#include <string>

namespace mixload {
// The current time as ISO 8601 UTC ("2026-11-25T16:32:29Z"), as records and files store it.
std::string utcNow();
// The instant `hours` from now, or none when hours <= 0 (no limit): a long driver's --max-hours.
std::optional<std::chrono::steady_clock::time_point> deadlineAfterHours(double hours);
// Wall seconds since t0 (steady clock): what runs, benchmarks and reduced models time themselves by.
inline double secondsSince(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace mixload
