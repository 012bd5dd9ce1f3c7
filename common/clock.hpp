// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>

namespace mixload {
// The current time as ISO 8601 UTC ("2026-11-25T16:32:29Z"), as records and files store it.
std::string utcNow();
}  // namespace mixload
