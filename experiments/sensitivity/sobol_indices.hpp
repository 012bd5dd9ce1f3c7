// SPDX-License-Identifier: GPL-3.0-or-later
// Global sensitivity of a function on the unit cube: first-order and total Sobol indices from
// quasi-random samples (Saltelli's first-order and Jansen's total estimators on the radial design
// A, B, A with column i from B), with bootstrap intervals over the sample rows.
#pragma once
#include <functional>
#include <vector>

namespace mixload::experiments {

struct SobolIndex {
    double first = 0, total = 0;                 // S_i, S_Ti
    double firstLo = 0, firstHi = 0, totalLo = 0, totalHi = 0;  // 90% bootstrap intervals
};

struct SobolIndices {
    std::vector<SobolIndex> inputs;
    double mean = 0, variance = 0;
    int n = 0, evaluations = 0, bootstrap = 0;
};

// f takes a point of [0,1)^k. n base rows (n (k + 2) evaluations); bootstrap resamples of the rows
// with a fixed seed, so the same call gives the same intervals. Throws InputError on n < 64,
// k < 1 or a function without variance over the cube.
SobolIndices sobolIndices(int k, const std::function<double(const std::vector<double>&)>& f, int n, int bootstrap = 500);

}  // namespace mixload::experiments
