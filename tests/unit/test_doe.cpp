// SPDX-License-Identifier: GPL-3.0-or-later
// Designs of experiments: Latin hypercube strata, maximin and extension, the Sobol sequence, the
// mu_d > mu_s constraint, and bad ranges files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "common/input_error.hpp"
#include "doe/adaptive.hpp"
#include "sensitivity/sobol_indices.hpp"
#include "doe/designs.hpp"
#include "doe/parameter_space.hpp"

using namespace mixload::experiments;

namespace {
const char* kMixerRanges = R"(scene = "mixer"
[mu_s]
min = 0.2
max = 0.45
unit = "1"
[delta_mu]
min = 0.05
max = 0.30
unit = "1"
[i0]
min = 0.1
max = 0.6
unit = "1"
[d]
min = 100e-6
max = 400e-6
unit = "m"
[rho]
min = 250
max = 600
unit = "kg/m3"
[feed_kg_h]
min = 5
max = 45
unit = "kg/h"
[rpm]
min = 39
max = 254
unit = "rpm"
)";

void expectBad(const std::string& text, const std::string& needle) {
    try {
        parseRanges(text, "test.toml");
        ADD_FAILURE() << "accepted: " << text;
    } catch (const mixload::InputError& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}
}  // namespace

TEST(Doe, LatinHypercubeHasOnePointPerStratumInEveryDimension) {
    for (int n : {1, 7, 40}) {
        const Design d = latinHypercube(n, 7, 42);
        ASSERT_EQ(d.size(), static_cast<size_t>(n));
        for (int c = 0; c < 7; ++c) {
            std::vector<int> strata;
            for (const auto& p : d) {
                ASSERT_GE(p[c], 0.0);
                ASSERT_LT(p[c], 1.0);
                strata.push_back(static_cast<int>(p[c] * n));
            }
            std::sort(strata.begin(), strata.end());
            for (int i = 0; i < n; ++i) EXPECT_EQ(strata[i], i) << "n " << n << " dim " << c;
        }
    }
}

TEST(Doe, LatinHypercubeIsSeededAndMaximin) {
    EXPECT_EQ(latinHypercube(20, 3, 7), latinHypercube(20, 3, 7));
    EXPECT_NE(latinHypercube(20, 3, 7), latinHypercube(20, 3, 8));
    // Picking the best of 200 hypercubes spreads the points: the smallest distance beats that of a
    // single random hypercube from the same seed.
    EXPECT_GT(minDistance(latinHypercube(20, 3, 7, 200)), minDistance(latinHypercube(20, 3, 7, 1)));
}

TEST(Doe, AugmentedLatinHypercubeAddsOnlyNewPointsInFreeStrata) {
    const Design old = latinHypercube(10, 4, 1);
    const Design extra = augmentLatinHypercube(old, 10, 2);
    ASSERT_EQ(extra.size(), 10u);
    for (int c = 0; c < 4; ++c) {
        std::set<int> strata;
        for (const auto& p : old) strata.insert(static_cast<int>(p[c] * 20));
        for (const auto& p : extra) {
            EXPECT_TRUE(strata.insert(static_cast<int>(p[c] * 20)).second)
                << "a new point shares a stratum (dim " << c << ")";
        }
    }
    // Here the old strata of the coarse division each hold one fine stratum, so the union of
    // 20 points is itself a Latin hypercube of 20.
    for (const auto& p : extra)
        for (const auto& q : old) EXPECT_NE(p, q);
}

TEST(Doe, SobolIsTheSobolSequenceAndExtendsWithoutRepeating) {
    // Dimension 1 is van der Corput in Gray-code order, dimension 2 has all direction numbers 1.
    const Design d = sobol(6, 2);
    const double x[6] = {0.5, 0.75, 0.25, 0.375, 0.875, 0.625};
    const double y[6] = {0.5, 0.25, 0.75, 0.375, 0.875, 0.125};
    for (int i = 0; i < 6; ++i) {
        EXPECT_DOUBLE_EQ(d[i][0], x[i]) << i;
        EXPECT_DOUBLE_EQ(d[i][1], y[i]) << i;
    }
    const Design all = sobol(16, 7);
    const Design first = sobol(8, 7), more = sobol(8, 7, 8);
    for (int i = 0; i < 8; ++i) {
        EXPECT_EQ(first[i], all[i]);
        EXPECT_EQ(more[i], all[8 + i]);
    }
    std::set<std::vector<double>> unique(all.begin(), all.end());
    EXPECT_EQ(unique.size(), all.size());
}

TEST(Doe, RangesMapTheCubeAndKeepMuDAboveMuS) {
    const ParameterSpace ps = parseRanges(kMixerRanges, "test.toml");
    EXPECT_EQ(ps.scene, "mixer");
    ASSERT_EQ(ps.params.size(), 7u);
    const Parameter* d = ps.find("d");
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(d->unit, "m");
    EXPECT_DOUBLE_EQ(d->max, 400e-6);
    const auto muS = std::find_if(ps.params.begin(), ps.params.end(), [](auto& p) { return p.name == "mu_s"; }) - ps.params.begin();
    const auto dMu = std::find_if(ps.params.begin(), ps.params.end(), [](auto& p) { return p.name == "delta_mu"; }) - ps.params.begin();
    for (const auto& u : latinHypercube(50, 7, 3)) {
        const auto x = ps.toPhysical(u);
        for (size_t j = 0; j < x.size(); ++j) {
            EXPECT_GE(x[j], ps.params[j].min);
            EXPECT_LE(x[j], ps.params[j].max);
        }
        EXPECT_GT(x[muS] + x[dMu], x[muS]);  // mu_d = mu_s + delta_mu
    }
}

TEST(Doe, BadRangesAreRefusedWithTheirName) {
    expectBad("scene = \"mixer\"\n[rho]\nmin = 600\nmax = 250\nunit = \"kg/m3\"\n", "rho.min");
    expectBad("scene = \"mixer\"\n[viscosity]\nmin = 1\nmax = 2\nunit = \"Pa s\"\n", "parameter = viscosity");
    expectBad("scene = \"mixer\"\n[d]\nmin = 100\nmax = 400\n", "d.unit = (missing)");
    expectBad("scene = \"mixer\"\n[d]\nmin = 100\nmax = 400\nunit = \"um\"\n", "d.unit = um");
    expectBad("scene = \"mixer\"\n[delta_mu]\nmin = -0.1\nmax = 0.2\nunit = \"1\"\n", "delta_mu.min");
    expectBad("scene = \"mixer\"\n[rpm]\nmin = 39\nmax = 254\nunit = \"rpm\"\nstep = 1\n", "rpm.step");
    expectBad("[rpm]\nmin = 39\nmax = 254\nunit = \"rpm\"\n", "scene = (missing)");
    expectBad("scene = \"mixer\"\n", "at least one parameter");
    expectBad("scene = \"mixer\"\n[rpm\n", "valid TOML");
    expectBad("scene = \"mixer\"\n[rpm]\nmin = 39\nmax = 254\nunit = \"rpm\"\nscale = \"ln\"\n", "rpm.scale = ln");
    expectBad("scene = \"mixer\"\n[feed_kg_h]\nmin = 0\nmax = 45\nunit = \"kg/h\"\nscale = \"log\"\n", "feed_kg_h.min = 0");
}

// A log-scaled range puts the middle of the cube at the geometric mean and round-trips.
TEST(Doe, LogScaledRangesAreEvenInTheLog) {
    const auto ps = parseRanges("scene = \"mixer\"\n[feed_kg_h]\nmin = 2.5\nmax = 62.5\nunit = \"kg/h\"\nscale = \"log\"\n"
                                "[rpm]\nmin = 39\nmax = 254\nunit = \"rpm\"\n",
                                "log.toml");
    ASSERT_TRUE(ps.find("feed_kg_h")->log);
    ASSERT_FALSE(ps.find("rpm")->log);
    const auto x = ps.toPhysical({0.5, 0.5});
    EXPECT_NEAR(x[0], 12.5, 1e-12);          // sqrt(2.5 * 62.5)
    EXPECT_NEAR(x[1], (39 + 254) / 2.0, 1e-12);
    EXPECT_NEAR(ps.toPhysical({0.0, 0.0})[0], 2.5, 1e-12);
    EXPECT_NEAR(ps.toPhysical({1.0, 1.0})[0], 62.5, 1e-12);
    const auto u = ps.toUnit({5.0, 100.0});
    EXPECT_NEAR(ps.toPhysical(u)[0], 5.0, 1e-12);
    EXPECT_NEAR(ps.toPhysical(u)[1], 100.0, 1e-12);
}

// The first adaptive point goes into the largest gap the finished and queued runs leave; the next
// ones do not pile onto it.
TEST(Doe, AdaptivePointsGoWhereTheModelIsLeastSure) {
    using namespace mixload::experiments;
    Design done;
    std::vector<double> y;
    for (double x : {0.0, 0.08, 0.16, 0.24, 0.32, 0.40}) done.push_back({x}), y.push_back(std::sin(4 * x));
    const Design pending{{1.0}};
    Design candidates;
    for (int i = 0; i <= 200; ++i) candidates.push_back({i / 200.0});
    const auto b = mostUncertain(done, y, pending, candidates, 3);
    ASSERT_EQ(b.picks.size(), 3u);
    // Inside the gap between 0.40 (finished) and 1.0 (queued), nearer the lone queued point than
    // the dense finished ones.
    EXPECT_GT(b.picks[0].unit[0], 0.6);
    EXPECT_LT(b.picks[0].unit[0], 0.9);
    EXPECT_NEAR(b.maxSdBefore, b.picks[0].sd, 1e-15);
    for (size_t i = 1; i < 3; ++i) {
        EXPECT_LE(b.picks[i].sd, b.picks[i - 1].sd * (1 + 1e-9)) << "conditioning on a pick cannot raise the largest sd";
        for (size_t j = 0; j < i; ++j) EXPECT_GT(std::abs(b.picks[i].unit[0] - b.picks[j].unit[0]), 0.05);
        EXPECT_GT(b.picks[i].unit[0], 0.4);
    }
    // Without the queued point the far end is the least known.
    EXPECT_GT(mostUncertain(done, y, {}, candidates, 1).picks[0].unit[0], 0.95);
    EXPECT_THROW(mostUncertain(Design(done.begin(), done.begin() + 4), std::vector<double>(y.begin(), y.begin() + 4), {}, candidates, 1),
                 mixload::InputError);
}

// A cost per point: the same model, but the upper half of the range costs 50 times the lower; per
// unit of cost the picks stay in the cheap half, and each says what it costs. A cost that is not
// positive is refused.
TEST(Doe, AdaptivePointsPerUnitOfCostGoWhereTheyAreCheap) {
    using namespace mixload::experiments;
    Design done;
    std::vector<double> y;
    for (double x : {0.0, 0.2, 0.4, 0.6, 0.8, 1.0}) done.push_back({x}), y.push_back(std::sin(4 * x));
    Design candidates;
    for (int i = 0; i <= 200; ++i) candidates.push_back({i / 200.0});
    const PointCost cost = [](const std::vector<double>& u, double) { return u[0] > 0.5 ? 50.0 : 1.0; };
    const auto plain = mostUncertain(done, y, {}, candidates, 4);
    const auto cheap = mostUncertain(done, y, {}, candidates, 3, AdaptiveCriterion::Variance, cost);
    // Without the cost the gaps are alike and the batch spreads over both halves.
    bool upper = false;
    for (const auto& p : plain.picks) {
        upper = upper || p.unit[0] > 0.5;
        EXPECT_EQ(p.cost, 0.0);
    }
    EXPECT_TRUE(upper);
    ASSERT_EQ(cheap.picks.size(), 3u);
    for (const auto& p : cheap.picks) {
        EXPECT_LE(p.unit[0], 0.5) << p.unit[0];
        EXPECT_EQ(p.cost, 1.0);
        EXPECT_EQ(p.weight, 1.0) << "the weight stays the criterion's own";
    }
    const PointCost free = [](const std::vector<double>&, double) { return 0.0; };
    EXPECT_THROW(mostUncertain(done, y, {}, candidates, 1, AdaptiveCriterion::Variance, free), mixload::InputError);
}

// The Ishigami function's Sobol indices are known in closed form (a = 7, b = 0.1): S = 0.3139,
// 0.4424, 0; S_T = 0.5576, 0.4424, 0.2437.
TEST(Sensitivity, SobolIndicesOfTheIshigamiFunction) {
    using namespace mixload::experiments;
    const double pi = std::acos(-1.0);
    const auto ishigami = [&](const std::vector<double>& u) {
        const double x1 = -pi + 2 * pi * u[0], x2 = -pi + 2 * pi * u[1], x3 = -pi + 2 * pi * u[2];
        return std::sin(x1) + 7 * std::sin(x2) * std::sin(x2) + 0.1 * std::pow(x3, 4) * std::sin(x1);
    };
    const auto s = sobolIndices(3, ishigami, 8192, 200);
    ASSERT_EQ(s.inputs.size(), 3u);
    EXPECT_EQ(s.evaluations, 8192 * 5);
    const double first[3] = {0.3139, 0.4424, 0.0}, total[3] = {0.5576, 0.4424, 0.2437};
    for (size_t i = 0; i < 3; ++i) {
        EXPECT_NEAR(s.inputs[i].first, first[i], 0.02) << i;
        EXPECT_NEAR(s.inputs[i].total, total[i], 0.02) << i;
        // The 90% bootstrap intervals bracket the estimate, and are narrow at this n.
        EXPECT_LE(s.inputs[i].firstLo, s.inputs[i].first);
        EXPECT_GE(s.inputs[i].firstHi, s.inputs[i].first);
        EXPECT_LT(s.inputs[i].totalHi - s.inputs[i].totalLo, 0.08) << i;
    }
    const double variance = 0.5 + 49.0 / 8 + 0.1 * std::pow(pi, 4) / 5 + 0.01 * std::pow(pi, 8) / 18;
    EXPECT_NEAR(s.variance, variance, 0.02 * variance);
    EXPECT_THROW(sobolIndices(3, ishigami, 10), mixload::InputError);
    EXPECT_THROW(sobolIndices(2, [](const std::vector<double>&) { return 1.0; }, 128), mixload::InputError);
}

// A step the runs straddle: the model misses the runs beside it (large leave-one-out errors) while
// its variance, which depends only on where runs are, is as large in every gap. loo-weighted puts
// the next points beside the step; the variance alone does not prefer it.
TEST(Doe, LooWeightedPointsGoWhereTheModelMissesItsRuns) {
    using namespace mixload::experiments;
    Design done;
    std::vector<double> y;
    for (int i = 0; i <= 10; ++i) {
        const double x = i / 10.0;
        done.push_back({x});
        y.push_back(x < 0.62 ? 0.0 : 3.0);  // a log loading that jumps by a factor of 20 across 0.62
    }
    Design candidates;
    for (int i = 0; i <= 400; ++i) candidates.push_back({i / 400.0});
    const auto weighted = mostUncertain(done, y, {}, candidates, 2, AdaptiveCriterion::LooWeighted);
    ASSERT_EQ(weighted.picks.size(), 2u);
    for (const auto& p : weighted.picks) {
        EXPECT_GT(p.unit[0], 0.5) << "beside the step";
        EXPECT_LT(p.unit[0], 0.8) << "beside the step";
        EXPECT_GT(p.weight, 1.5);
    }
    EXPECT_GT(std::abs(weighted.picks[0].unit[0] - weighted.picks[1].unit[0]), 0.02) << "a batch spreads out";
    const auto plain = mostUncertain(done, y, {}, candidates, 1);
    EXPECT_EQ(plain.picks[0].weight, 1.0);
    EXPECT_NEAR(plain.maxSdBefore, weighted.maxSdBefore, 1e-12) << "the same model before either batch";
    // The variance's largest gap is not the step's: the ends of the range, half a gap from one run.
    EXPECT_TRUE(plain.picks[0].unit[0] < 0.5 || plain.picks[0].unit[0] > 0.8) << plain.picks[0].unit[0];
}
