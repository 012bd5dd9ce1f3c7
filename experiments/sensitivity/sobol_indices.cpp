// SPDX-License-Identifier: GPL-3.0-or-later
#include "sensitivity/sobol_indices.hpp"

#include <algorithm>
#include <random>
#include <string>

#include "common/input_error.hpp"
#include "common/stats.hpp"
#include "doe/designs.hpp"

namespace mixload::experiments {

namespace {

struct Estimate {
    double variance = 0;
    std::vector<double> first, total;
};

// The estimators over the rows in `rows` (a bootstrap sample, or every row once).
Estimate estimate(const std::vector<double>& fA, const std::vector<double>& fB, const std::vector<std::vector<double>>& fAB,
                  const std::vector<int>& rows) {
    const auto m = static_cast<double>(rows.size());
    double s = 0, s2 = 0;
    for (int j : rows) s += fA[j] + fB[j], s2 += fA[j] * fA[j] + fB[j] * fB[j];
    const double mean = s / (2 * m);
    Estimate e;
    e.variance = s2 / (2 * m) - mean * mean;
    for (const auto& fi : fAB) {
        double first = 0, total = 0;
        for (int j : rows) {
            first += fB[j] * (fi[j] - fA[j]);
            total += (fA[j] - fi[j]) * (fA[j] - fi[j]);
        }
        e.first.push_back(first / m / e.variance);
        e.total.push_back(total / (2 * m) / e.variance);
    }
    return e;
}

}  // namespace

SobolIndices sobolIndices(int k, const std::function<double(const std::vector<double>&)>& f, int n, int bootstrap) {
    if (k < 1) throw InputError("inputs", std::to_string(k), "at least 1");
    if (n < 64) throw InputError("n", std::to_string(n), ">= 64 base samples");
    if (bootstrap < 0) throw InputError("bootstrap", std::to_string(bootstrap), ">= 0");
    // One Sobol point of dimension 2k gives the rows of A (its first k coordinates) and B.
    const auto points = sobol(n, 2 * k, 1);
    std::vector<double> fA(static_cast<size_t>(n)), fB(static_cast<size_t>(n));
    std::vector<std::vector<double>> fAB(static_cast<size_t>(k), std::vector<double>(static_cast<size_t>(n)));
    for (int j = 0; j < n; ++j) {
        const auto& p = points[static_cast<size_t>(j)];
        const std::vector<double> a(p.begin(), p.begin() + k), b(p.begin() + k, p.end());
        fA[static_cast<size_t>(j)] = f(a);
        fB[static_cast<size_t>(j)] = f(b);
        for (int i = 0; i < k; ++i) {
            auto ab = a;
            ab[static_cast<size_t>(i)] = b[static_cast<size_t>(i)];
            fAB[static_cast<size_t>(i)][static_cast<size_t>(j)] = f(ab);
        }
    }
    std::vector<int> all(static_cast<size_t>(n));
    for (int j = 0; j < n; ++j) all[static_cast<size_t>(j)] = j;
    const auto e = estimate(fA, fB, fAB, all);
    if (!(e.variance > 0)) throw InputError("model", "constant over the ranges", "a loading that varies over them");
    SobolIndices out;
    out.n = n;
    out.evaluations = n * (k + 2);
    out.bootstrap = bootstrap;
    out.variance = e.variance;
    double s = 0;
    for (int j = 0; j < n; ++j) s += fA[static_cast<size_t>(j)] + fB[static_cast<size_t>(j)];
    out.mean = s / (2.0 * n);
    std::vector<std::vector<double>> bf(static_cast<size_t>(k)), bt(static_cast<size_t>(k));
    std::mt19937 gen(1);
    std::vector<int> rows(static_cast<size_t>(n));
    for (int b = 0; b < bootstrap; ++b) {
        for (auto& r : rows) r = static_cast<int>(gen() % static_cast<unsigned>(n));
        const auto eb = estimate(fA, fB, fAB, rows);
        for (int i = 0; i < k; ++i) bf[static_cast<size_t>(i)].push_back(eb.first[static_cast<size_t>(i)]), bt[static_cast<size_t>(i)].push_back(eb.total[static_cast<size_t>(i)]);
    }
    for (int i = 0; i < k; ++i) {
        SobolIndex ix;
        ix.first = e.first[static_cast<size_t>(i)];
        ix.total = e.total[static_cast<size_t>(i)];
        if (bootstrap > 0) {
            ix.firstLo = percentile(bf[static_cast<size_t>(i)], 0.05);
            ix.firstHi = percentile(bf[static_cast<size_t>(i)], 0.95);
            ix.totalLo = percentile(bt[static_cast<size_t>(i)], 0.05);
            ix.totalHi = percentile(bt[static_cast<size_t>(i)], 0.95);
        } else {
            ix.firstLo = ix.firstHi = ix.first;
            ix.totalLo = ix.totalHi = ix.total;
        }
        out.inputs.push_back(ix);
    }
    return out;
}

}  // namespace mixload::experiments
