// SPDX-License-Identifier: GPL-3.0-or-later
#include "doe/designs.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <random>
#include <set>

#include <gsl/gsl_qrng.h>

#include "common/input_error.hpp"

namespace mixload::experiments {

namespace {

double minDistanceBetween(const Design& a, const Design& b, bool same) {
    double best = INFINITY;
    for (size_t i = 0; i < a.size(); ++i)
        for (size_t j = same ? i + 1 : 0; j < b.size(); ++j) {
            double s = 0;
            for (size_t c = 0; c < a[i].size(); ++c) s += (a[i][c] - b[j][c]) * (a[i][c] - b[j][c]);
            best = std::min(best, s);
        }
    return std::sqrt(best);
}

// Fills column c of n points from the given strata (one per point, in the order given) of a
// division into `total` strata, each point uniform inside its stratum.
void fillColumn(Design& d, size_t c, const std::vector<int>& strata, int total, std::mt19937_64& rng) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (size_t i = 0; i < d.size(); ++i) d[i][c] = (strata[i] + u(rng)) / total;
}

}  // namespace

double minDistance(const Design& d) { return d.size() < 2 ? 0.0 : minDistanceBetween(d, d, true); }

Design latinHypercube(int n, int k, std::uint64_t seed, int candidates) {
    requireRange("n", n, 1, 1e6);
    requireRange("dimensions", k, 1, 1000);
    std::mt19937_64 rng(seed);
    Design best;
    double bestScore = -1;
    for (int trial = 0; trial < std::max(1, candidates); ++trial) {
        Design d(n, std::vector<double>(k));
        for (int c = 0; c < k; ++c) {
            std::vector<int> perm(n);
            std::iota(perm.begin(), perm.end(), 0);
            std::shuffle(perm.begin(), perm.end(), rng);
            fillColumn(d, c, perm, n, rng);
        }
        const double score = minDistance(d);
        if (score > bestScore) bestScore = score, best = std::move(d);
    }
    return best;
}

Design augmentLatinHypercube(const Design& existing, int m, std::uint64_t seed, int candidates) {
    requireRange("n", m, 1, 1e6);
    if (existing.empty()) return latinHypercube(m, 1, seed, candidates);
    const int k = static_cast<int>(existing.front().size());
    const int total = static_cast<int>(existing.size()) + m;
    std::mt19937_64 rng(seed);
    // Per dimension: strata of the n+m division left empty by the old points (at least m of them).
    std::vector<std::vector<int>> freeStrata(k);
    for (int c = 0; c < k; ++c) {
        std::set<int> used;
        for (const auto& p : existing) used.insert(std::min(total - 1, static_cast<int>(p[c] * total)));
        for (int s = 0; s < total; ++s)
            if (!used.count(s)) freeStrata[c].push_back(s);
    }
    Design best;
    double bestScore = -1;
    for (int trial = 0; trial < std::max(1, candidates); ++trial) {
        Design d(m, std::vector<double>(k));
        for (int c = 0; c < k; ++c) {
            std::vector<int> pick = freeStrata[c];
            std::shuffle(pick.begin(), pick.end(), rng);
            pick.resize(m);
            fillColumn(d, c, pick, total, rng);
        }
        // Maximin over the union: new points far from each other and from the old ones.
        const double within = m < 2 ? INFINITY : minDistance(d);
        const double score = std::min(within, minDistanceBetween(d, existing, false));
        if (score > bestScore) bestScore = score, best = std::move(d);
    }
    return best;
}

Design sobol(int n, int k, int skip) {
    requireRange("n", n, 1, 1e7);
    requireRange("dimensions", k, 1, 40);  // GSL's Sobol generator
    requireRange("skip", skip, 0, 1e9);
    std::unique_ptr<gsl_qrng, decltype(&gsl_qrng_free)> q(gsl_qrng_alloc(gsl_qrng_sobol, k),
                                                          gsl_qrng_free);
    std::vector<double> x(k);
    for (int i = 0; i < skip; ++i) gsl_qrng_get(q.get(), x.data());
    Design d(n, std::vector<double>(k));
    for (int i = 0; i < n; ++i) gsl_qrng_get(q.get(), d[i].data());
    return d;
}

}  // namespace mixload::experiments
