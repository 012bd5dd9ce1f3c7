// SPDX-License-Identifier: GPL-3.0-or-later
// The steady-loading test of the mixer monitor on synthetic histories.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "steadyLoading.H"

using mixload::steady::test;

namespace {
struct History {
    std::vector<double> t, M, C;
};

// M(t) given; the cumulative outflow follows from a constant feed and the mass balance.
template <class F>
History make(double end, double dt, double feed, F loading) {
    History h;
    double out = 0;
    for (double t = 0; t <= end + 1e-12; t += dt) {
        if (!h.t.empty()) out += feed * dt - (loading(t) - h.M.back());
        h.t.push_back(t);
        h.M.push_back(loading(t));
        h.C.push_back(out);
    }
    return h;
}

constexpr double kFeed = 5.0 / 3600;  // kg/s
constexpr double kRev = 60.0 / 39;    // s
constexpr double kW = 3 * kRev;
}  // namespace

TEST(SteadyLoading, ConstantLoadingIsSteady) {
    const auto h = make(20, 0.01, kFeed, [](double) { return 0.3; });
    const auto v = test(h.t, h.M, h.C, kW, kFeed, 0.02, 0.1, 0);
    EXPECT_TRUE(v.steady);
    EXPECT_NEAR(v.meanLoading, 0.3, 1e-12);
    EXPECT_NEAR(v.meanOutflow, kFeed, 1e-9);
}

TEST(SteadyLoading, PeriodicLoadingAveragedOverWholeRevolutionsIsSteady) {
    // Paddle passing: 12 paddles -> 12 bumps per revolution, plus a once-per-revolution swing.
    const auto h = make(20, 0.002, kFeed, [](double t) {
        return 0.3 + 0.01 * std::sin(2 * std::numbers::pi * t / kRev) + 0.004 * std::sin(24 * std::numbers::pi * t / kRev);
    });
    const auto v = test(h.t, h.M, h.C, kW, kFeed, 0.02, 0.1, 0);
    EXPECT_TRUE(v.steady) << "drift " << v.drift << " flow error " << v.flowError;
    EXPECT_NEAR(v.meanLoading, 0.3, 1e-4);
}

TEST(SteadyLoading, SlowlyFillingMixerIsNotSteady) {
    // Filling at half the feed: the loading changes by well under 2% per window, but the outflow
    // is only half the feed, which the flow condition catches.
    const auto h = make(30, 0.01, kFeed, [](double t) { return 0.2 + 0.5 * kFeed * t; });
    const auto v = test(h.t, h.M, h.C, kW, kFeed, 0.02, 0.1, 0);
    EXPECT_LT(v.drift, 0.02);
    EXPECT_FALSE(v.steady);
    EXPECT_NEAR(v.flowError, 0.5, 1e-6);
}

TEST(SteadyLoading, DrainingMixerIsNotSteady) {
    const auto h = make(20, 0.01, kFeed, [](double t) { return 0.4 * std::exp(-t / 10); });
    EXPECT_FALSE(test(h.t, h.M, h.C, kW, kFeed, 0.02, 0.1, 0).steady);
}

TEST(SteadyLoading, NoisyLoadingIsJudgedByItsWindowMeans) {
    // Paddle-scale noise on M with a steady discharge: steady. The same noise on a mixer that
    // fills at half the feed: not steady.
    std::mt19937 rng(42);
    std::normal_distribution<double> noise(0, 0.005);
    History quiet, filling;
    for (double t = 0; t <= 20; t += 0.01) {
        quiet.t.push_back(t);
        quiet.M.push_back(0.3 + noise(rng));
        quiet.C.push_back(kFeed * t);
        filling.t.push_back(t);
        filling.M.push_back(0.2 + 0.5 * kFeed * t + noise(rng));
        filling.C.push_back(0.5 * kFeed * t);
    }
    const auto q = test(quiet.t, quiet.M, quiet.C, kW, kFeed, 0.02, 0.1, 0);
    EXPECT_TRUE(q.steady) << "drift " << q.drift;
    EXPECT_NEAR(q.meanLoading, 0.3, 0.002);
    EXPECT_FALSE(test(filling.t, filling.M, filling.C, kW, kFeed, 0.02, 0.1, 0).steady);
}

TEST(SteadyLoading, NeedsTwoWindowsAfterMinTime) {
    const auto h = make(5, 0.01, kFeed, [](double) { return 0.3; });
    EXPECT_FALSE(test(h.t, h.M, h.C, 3.0, kFeed, 0.02, 0.1, 0).enoughHistory);  // 6 s > 5 s
    EXPECT_TRUE(test(h.t, h.M, h.C, 2.0, kFeed, 0.02, 0.1, 0).steady);
    EXPECT_FALSE(test(h.t, h.M, h.C, 2.0, kFeed, 0.02, 0.1, 2.0).steady);  // window starts at 1
}

TEST(SteadyLoading, NoFeedRestingBedIsSteady) {
    const auto h = make(10, 0.01, 0.0, [](double) { return 0.3; });
    EXPECT_TRUE(test(h.t, h.M, h.C, 2.0, 0.0, 0.02, 0.1, 0).steady);
}

TEST(SteadyLoading, WindowCoversAShareOfTheResidenceTimeInWholeRevolutions) {
    using mixload::steady::windowLength;
    // 0.02 kg at 5 kg/h: residence 14.4 s, half of it 7.2 s -> 5 revolutions of 60/39 s.
    EXPECT_NEAR(windowLength(kW, kRev, 0.5, 0.02, kFeed), 5 * kRev, 1e-12);
    // A nearly empty mixer keeps the revolutions' window, and fraction 0 is the old rule.
    EXPECT_NEAR(windowLength(kW, kRev, 0.5, 1e-4, kFeed), kW, 1e-12);
    EXPECT_NEAR(windowLength(kW, kRev, 0.0, 0.02, kFeed), kW, 1e-12);
    // No feed (resting bed) or no period: no residence time, no rounding.
    EXPECT_NEAR(windowLength(2.5, 0, 0.5, 0.3, 0), 2.5, 1e-12);
    EXPECT_NEAR(windowLength(2.5, 0, 0.5, 0.02, kFeed), 7.2, 1e-12);
}

TEST(SteadyLoading, SlowOscillationLongerThanTheRevolutionsWindowIsNotSteady) {
    // A loading that wanders by +-6% with a 20 s period (as measured at 254 rpm, 5 kg/h) and a
    // window of 3 revolutions at 254 rpm: two 0.7 s windows near a crest agree, a window of half
    // the residence time does not.
    const double rev = 60.0 / 254, feed = kFeed;
    const auto M = [](double t) { return 0.0187 * (1 + 0.06 * std::sin(2 * std::numbers::pi * t / 20.0)); };
    const auto h = make(35.0, 0.005, feed, M);  // ends near a crest (t = 25 s + 10 s)
    const double shortW = 3 * rev;
    const double longW = mixload::steady::windowLength(shortW, rev, 0.5, h.M.back(), feed);
    EXPECT_GT(longW, 20 * shortW / 3 / 2);
    EXPECT_LT(test(h.t, h.M, h.C, shortW, feed, 0.01, 1.0, 0).drift, 0.01);
    EXPECT_FALSE(test(h.t, h.M, h.C, longW, feed, 0.01, 1.0, 0).steady);
}

namespace {
// The first sample time at which the balance test calls the history steady (or -1), scanning the
// history as the monitor does, one prefix at a time.
template <class Test>
double firstSteady(const History& h, double from, double every, Test verdict) {
    for (double end = from; end <= h.t.back() + 1e-12; end += every) {
        const auto n = static_cast<std::size_t>(std::upper_bound(h.t.begin(), h.t.end(), end + 1e-12) - h.t.begin());
        const std::vector<double> t(h.t.begin(), h.t.begin() + n), M(h.M.begin(), h.M.begin() + n),
            C(h.C.begin(), h.C.begin() + n);
        if (verdict(t, M, C)) return t.back();
    }
    return -1;
}
}  // namespace

// The balance test as the monitor calls it: windows of w, and the window test's window of half
// the residence time in whole periods.
mixload::steady::BalanceVerdict testBalance(const std::vector<double>& t, const std::vector<double>& M,
                                            const std::vector<double>& C, double w, double feed,
                                            double tol, double flowTol, double minTime,
                                            double period = kRev) {
    const double wres = mixload::steady::windowLength(w, period, 0.5, M.back(), feed);
    return mixload::steady::testBalance(t, M, C, w, wres, feed, tol, flowTol, minTime);
}

TEST(SteadyBalance, RelaxationIsSteadyOnceTheChangeToComeIsWithinTolerance) {
    // M relaxes to 0.024 kg with tau = 11 s from 20% above (the 39 rpm, 5 kg/h run's shape).
    const double tau = 11, Minf = 0.024;
    const auto h = make(80, 0.01, kFeed, [&](double t) { return Minf * (1 + 0.2 * std::exp(-t / tau)); });
    auto balance = [&](const auto& t, const auto& M, const auto& C) {
        return testBalance(t, M, C, kW, kFeed, 0.01, 0.03, 0).steady;
    };
    const double at = firstSteady(h, kW, 0.1, balance);
    ASSERT_GT(at, 0);
    // Called when the loading is within 1% of where it goes, and not long after.
    const double M = Minf * (1 + 0.2 * std::exp(-at / tau));
    EXPECT_LE(std::abs(M - Minf) / Minf, 0.01) << "at " << at;
    EXPECT_LT(at, tau * std::log(20.0) + 3 * kW);
    // Earlier than the window test, by the balance.
    auto windows = [&](const auto& t, const auto& M, const auto& C) {
        const double W = mixload::steady::windowLength(kW, kRev, 0.5, M.back(), kFeed);
        return test(t, M, C, W, kFeed, 0.01, 0.03, 0).steady;
    };
    EXPECT_LT(at, firstSteady(h, kW, 0.1, windows) - 1.0);
    // The relaxation time is read off the history, and the verdict came from the balance.
    const auto n = static_cast<std::size_t>(std::upper_bound(h.t.begin(), h.t.end(), at + 1e-12) - h.t.begin());
    const std::vector<double> pt(h.t.begin(), h.t.begin() + n), pM(h.M.begin(), h.M.begin() + n),
        pC(h.C.begin(), h.C.begin() + n);
    const auto v = testBalance(pt, pM, pC, kW, kFeed, 0.01, 0.03, 0);
    EXPECT_TRUE(v.byBalance);
    EXPECT_NEAR(v.tau, tau, 0.1 * tau);
}

TEST(SteadyBalance, FlatHistoryIsHeldForAResidenceTime) {
    // A run started from a finished field: the loading is flat (paddle ripple on top). A crest of a
    // slow oscillation looks the same for a while, so the balance test leaves it to the window
    // test, which waits for two windows of half the residence time M/feed (17.3 s here).
    const auto h = make(40, 0.005, kFeed, [](double t) {
        return 0.024 * (1 + 0.003 * std::sin(24 * std::numbers::pi * t / kRev));
    });
    auto balance = [&](const auto& t, const auto& M, const auto& C) {
        return testBalance(t, M, C, kW, kFeed, 0.01, 0.03, 0).steady;
    };
    const double at = firstSteady(h, kW, 0.1, balance);
    EXPECT_GE(at, 0.024 / kFeed);
    EXPECT_LE(at, 0.024 / kFeed + kW + 0.2);
}

TEST(SteadyBalance, FillingAndDrainingAreNotSteady) {
    const auto filling = make(30, 0.01, kFeed, [](double t) { return 0.02 + 0.5 * kFeed * t; });
    EXPECT_FALSE(testBalance(filling.t, filling.M, filling.C, kW, kFeed, 0.01, 0.03, 0).steady);
    const auto draining = make(30, 0.01, kFeed, [](double t) { return 0.4 * std::exp(-t / 10); });
    EXPECT_FALSE(testBalance(draining.t, draining.M, draining.C, kW, kFeed, 0.01, 0.03, 0).steady);
    // Without feed there is no balance: the window test's verdict (a resting bed is steady).
    const auto still = make(30, 0.01, 0.0, [](double) { return 0.3; });
    const auto v = testBalance(still.t, still.M, still.C, kW, 0.0, 0.01, 0.03, 0);
    EXPECT_TRUE(v.steady);
    EXPECT_FALSE(v.byBalance);
}

TEST(SteadyBalance, SlowOscillationIsNeverSteady) {
    // The 254 rpm, 5 kg/h wandering (+-6%, 20 s period) with 3-revolution windows: the outflow is
    // out of phase with the loading, so the relaxation time falls back to M/feed, and no prefix of
    // a minute of history is called steady, crests included.
    const double rev = 60.0 / 254;
    const auto h = make(60.0, 0.005, kFeed, [](double t) {
        return 0.0187 * (1 + 0.06 * std::sin(2 * std::numbers::pi * t / 20.0));
    });
    auto balance = [&](const auto& t, const auto& M, const auto& C) {
        return testBalance(t, M, C, 3 * rev, kFeed, 0.01, 0.03, 0, rev).steady;
    };
    EXPECT_LT(firstSteady(h, 3 * rev, 0.05, balance), 0);
}

TEST(SteadyBalance, SmallSlowOscillationAboveToleranceIsNeverSteady) {
    // +-2% at a 20 s period, 254 rpm windows: the neighbours of a crest alone would pass; the
    // wandering history (loading and outflow uncorrelated) holds the verdict for a residence time.
    const double rev = 60.0 / 254;
    const auto h = make(60.0, 0.005, kFeed, [](double t) {
        return 0.0187 * (1 + 0.02 * std::sin(2 * std::numbers::pi * t / 20.0));
    });
    auto balance = [&](const auto& t, const auto& M, const auto& C) {
        return testBalance(t, M, C, 3 * rev, kFeed, 0.01, 0.03, 0, rev).steady;
    };
    EXPECT_LT(firstSteady(h, 3 * rev, 0.05, balance), 0);
}
