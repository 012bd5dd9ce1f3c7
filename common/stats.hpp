// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <algorithm>
#include <cmath>
#include <array>
#include <cstddef>
#include <random>
#include <vector>

namespace mixload {
// The median (mean of the middle two for an even count); NaN for no values.
inline double median(std::vector<double> v) {
    if (v.empty()) return std::nan("");
    std::sort(v.begin(), v.end());
    const size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

// The p-quantile of a sample (bootstrap replicates, Monte Carlo draws) as its order statistic of
// rank round((n - 1) p). n >= 1.
inline double percentile(std::vector<double> v, double p) {
    const auto k = static_cast<std::size_t>(std::lround(p * static_cast<double>(v.size() - 1)));
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
    return v[k];
}

// 90% bootstrap interval of a sample's mean (percentiles of 2000 resampled means, a fixed seed: the
// same sample gives the same interval). Of a paired difference (method A's error minus method B's,
// run by run) it says whether a few dozen runs can tell the two apart. n >= 2.
inline std::array<double, 2> bootstrapMeanInterval90(const std::vector<double>& v) {
    std::mt19937 gen(1);
    constexpr int kResamples = 2000;
    const std::size_t n = v.size();
    std::vector<double> means(kResamples);
    for (auto& m : means) {
        double s = 0;
        for (std::size_t i = 0; i < n; ++i) s += v[gen() % n];
        m = s / static_cast<double>(n);
    }
    return {percentile(means, 0.05), percentile(means, 0.95)};
}
}  // namespace mixload
