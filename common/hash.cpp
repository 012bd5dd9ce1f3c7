// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/hash.hpp"

#include <cstdint>
#include <cstdio>

namespace mixload {
std::string stableHash(const std::string& text) {
    std::uint64_t h = 14695981039346656037ULL;
    for (unsigned char c : text) {
        h ^= c;
        h *= 1099511628211ULL;
    }
    char buf[17];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(h));
    return buf;
}
}  // namespace mixload
