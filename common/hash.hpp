// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <string>

namespace mixload {
// Stable 64-bit FNV-1a of a string, as 16 hex digits. Used on a scene's canonical JSON text to name
// its run directory; collisions are not a security concern here.
std::string stableHash(const std::string& text);
}  // namespace mixload
