// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

namespace mixload::experiments {

// A study row that is a result: it has a loading, a steady verdict, and its powder balance
// closed (rows without a balance, from before it was measured, count as closed).
inline bool isResult(const nlohmann::json& r) {
    return r.contains("loading_kg") && r.value("steady", false) && r.value("powder_balance_ok", true);
}

// Where a study row's run started: "mrf" for a sliding-mesh run started from the MRF run's fields
// at its point (study mixer --sm-from-mrf), "sm" for one that continues the sliding-mesh run at the
// next higher feed (--sm-down-feeds), else "deposit".
inline std::string startOf(const nlohmann::json& r) { return r.value("start", "deposit"); }

// How the study's tables name a start (one wording for `study mixer` and the methods table).
inline std::string startLabel(const std::string& start) {
    return start == "mrf" ? "MRF's fields" : start == "sm" ? "SM at the next higher feed" : "the deposit";
}

// A number of a result as a markdown table cell in printf format, "-" when the result has none.
inline std::string tableCell(const nlohmann::json& v, const char* format) {
    if (v.is_null()) return "-";
    char b[64];
    std::snprintf(b, sizeof b, format, v.get<double>());
    return b;
}

}  // namespace mixload::experiments
