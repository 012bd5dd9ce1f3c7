// SPDX-License-Identifier: GPL-3.0-or-later
// Synthetic training runs for the surrogate tests: n points drawn by `draw` from a seeded uniform
// generator, each labelled by `law`.
#pragma once
#include <random>
#include <string>
#include <vector>

#include "table.hpp"

namespace mixload::testing {

template <class Draw, class Law>
std::vector<surrogates::Row> syntheticRuns(int n, unsigned seed, const std::string& prefix, Draw draw, Law law) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<double> u(0, 1);
    const auto uniform = [&] { return u(g); };
    std::vector<surrogates::Row> out;
    for (int i = 0; i < n; ++i) {
        surrogates::Row r;
        r.id = prefix + std::to_string(seed) + "-" + std::to_string(i);
        r.x = draw(uniform);
        r.m = law(r.x);
        out.push_back(r);
    }
    return out;
}

}  // namespace mixload::testing
