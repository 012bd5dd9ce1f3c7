// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

namespace mixload::experiments {

// A number of a result as a markdown table cell in printf format, "-" when the result has none.
inline std::string tableCell(const nlohmann::json& v, const char* format) {
    if (v.is_null()) return "-";
    char b[64];
    std::snprintf(b, sizeof b, format, v.get<double>());
    return b;
}

}  // namespace mixload::experiments
