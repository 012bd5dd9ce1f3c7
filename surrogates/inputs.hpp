// SPDX-License-Identifier: GPL-3.0-or-later
// The seven inputs every mixer-loading surrogate takes, in SI units as the CLI flags take them.
#pragma once
#include <array>
#include <string>

namespace mixload::surrogates {

inline constexpr int kInputs = 7;
using Point = std::array<double, kInputs>;
// Each input's place in a Point (and in kInputSpecs).
enum Input : int { kMuS = 0, kMuD, kI0, kD, kRho, kFeed, kRpm };

struct InputSpec {
    const char* name;  // column name in tables and model files
    const char* unit;
    const char* flag;  // CLI flag
    bool positive;     // strictly positive physical quantity (log transform allowed)
};

inline constexpr std::array<InputSpec, kInputs> kInputSpecs{{
    {"mu_s", "1", "--mu-s", true},
    {"mu_d", "1", "--mu-d", true},
    {"i0", "1", "--i0", true},
    {"d", "m", "--d", true},
    {"rho", "kg/m3", "--rho", true},
    {"feed_kg_h", "kg/h", "--feed-kg-h", true},
    {"rpm", "rpm", "--rpm", true},
}};

inline constexpr const char* kOutputName = "loading_kg";

}  // namespace mixload::surrogates
