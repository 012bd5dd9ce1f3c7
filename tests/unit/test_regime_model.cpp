// SPDX-License-Identifier: GPL-3.0-or-later
// The regime model (issue 64) on a synthetic loading that falls tenfold across the bed-to-film
// band, and the two-states rule that labels a point whose replicate sits in another state.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/input_error.hpp"
#include "model.hpp"
#include "regime.hpp"
#include "synthetic_runs.hpp"
#include "table.hpp"

using namespace mixload::surrogates;

namespace {

// A bed (M ~ feed^0.6 rpm^-0.3) that collapses to a film of a few seconds' residence above ~170 rpm.
double law(const Point& x) {
    const double bed = 0.2 * std::pow(x[kFeed] / 20, 0.6) * std::pow(x[kRpm] / 100, -0.3);
    const double film = x[kFeed] / 3600 * 4.0 * std::pow(x[kRpm] / 220, -0.5);
    const double w = 1 / (1 + std::exp((x[kRpm] - 172) / 8));
    return w * bed + (1 - w) * film;
}

std::vector<Row> rows(int n, unsigned seed) {
    return mixload::testing::syntheticRuns(n, seed, "r", [](auto u) {
        const double mus = 0.2 + 0.25 * u();
        return Point{mus, mus + 0.1 + 0.2 * u(), 0.28, 300e-6, 330, 3 + 55 * u(), 40 + 215 * u()};
    }, law);
}

double meanError(const Surrogate& m, const std::vector<Row>& test) {
    auto ws = m.makeWorkspace();
    double e = 0;
    for (const auto& r : test) e += std::abs(m.predict(r.x, ws).m - r.m) / r.m;
    return e / static_cast<double>(test.size());
}

}  // namespace

TEST(RegimeModel, BeatsOneKrigingAcrossTheBandAndRoundTrips) {
    const auto train = rows(60, 1), test = rows(60, 2);
    FitOptions o;
    o.kind = "kriging";
    const auto one = Surrogate::fit(train, o, {});
    o.kind = "regimes";
    const auto reg = Surrogate::fit(train, o, {});
    ASSERT_EQ(reg.parts().size(), 3u);
    const double eOne = meanError(one, test), eReg = meanError(reg, test);
    EXPECT_LT(eReg, eOne) << "regimes " << eReg << ", one kriging " << eOne;
    const auto back = Surrogate::fromJson(reg.toJson());
    auto a = reg.makeWorkspace(), b = back.makeWorkspace();
    for (const auto& r : test) EXPECT_EQ(reg.predict(r.x, a).m, back.predict(r.x, b).m);
    // No jump at a boundary: the blend hands over within a few rpm.
    Point x = test[0].x;
    for (double rpm : {kBedMaxRpm, kFilmMinRpm}) {
        x[kRpm] = rpm - 0.01;
        const double below = reg.predict(x, a).m;
        x[kRpm] = rpm + 0.01;
        EXPECT_NEAR(reg.predict(x, a).m, below, 0.01 * below) << rpm;
    }
}

// (Allocation-free prediction: SurrogateModel.PredictionDoesNotAllocate covers this kind too.)
TEST(RegimeModel, IntervalsStayPhysical) {
    FitOptions o;
    o.kind = "regimes";
    const auto m = Surrogate::fit(rows(60, 3), o, {});
    const auto pts = rows(200, 4);
    auto ws = m.makeWorkspace();
    for (const auto& p : pts) {
        const auto q = m.predict(p.x, ws);
        EXPECT_GE(q.lo, 0);
        EXPECT_LE(q.lo, q.m);
        EXPECT_GE(q.hi, q.m);
    }
    // Across regimes the difference's interval still holds the difference of the means.
    Point bed = pts[0].x, film = pts[0].x;
    bed[kRpm] = 80, film[kRpm] = 240;
    const auto d = m.predictDifference(bed, film);
    EXPECT_LT(d.lo, d.dm);
    EXPECT_GT(d.hi, d.dm);
}

TEST(RegimeModel, TooFewFilmRunsIsAClearError) {
    auto train = rows(60, 5);
    std::erase_if(train, [](const Row& r) { return r.x[kRpm] > kFilmMinRpm; });
    FitOptions o;
    o.kind = "regimes";
    EXPECT_THROW(Surrogate::fit(train, o, {}), mixload::InputError);
}

TEST(TwoStates, APointInTwoStatesTakesTheProtocolsStart) {
    Table t;
    Row a{"a", {0.3, 0.5, 0.28, 3e-4, 330, 17.6, 250}, 0.110, -1};  // warm start, dense bed kept
    Row b{"b", {0.3, 0.5, 0.28, 3e-4, 330, 10, 100}, 0.30, 0.32};
    t.rows = {a, b};
    Row ra = a, rb = b;
    ra.id = "a2", ra.m = 0.0161, ra.depositKg = 0.055;  // a film from a small deposit
    rb.id = "b2", rb.m = 0.31, rb.depositKg = 0.1;      // one state, label noise
    t.replicateRuns = {ra, rb};
    auto p = t;
    const auto report = resolveTwoStates(p, TwoStates::Protocol, 0.05);
    ASSERT_EQ(report.size(), 1u);
    EXPECT_EQ(report[0]["id"], "a");
    ASSERT_EQ(p.rows.size(), 2u);
    EXPECT_DOUBLE_EQ(p.rows[0].m, 0.0161);
    EXPECT_DOUBLE_EQ(p.rows[1].m, 0.30);
    auto d = t;
    resolveTwoStates(d, TwoStates::Drop, 0.05);
    ASSERT_EQ(d.rows.size(), 1u);
    EXPECT_EQ(d.rows[0].id, "b");
    auto k = t;
    resolveTwoStates(k, TwoStates::Keep, 0.05);
    EXPECT_DOUBLE_EQ(k.rows[0].m, 0.110);
    EXPECT_THROW(twoStatesFromString("both"), mixload::InputError);
}
