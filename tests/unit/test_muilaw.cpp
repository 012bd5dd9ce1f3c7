// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>

#include "muILaw.H"

using namespace mixload::rheology;

namespace {
const MuIParams kJop{0.382, 0.643, 0.279};
const MuIParams kAvicel{0.31, 0.44, 0.28};
const MuIParams kQuartzPaper{1.33, 1.69, 0.30};
}  // namespace

TEST(MuILaw, LimitsAreMuSAndMuD) {
    EXPECT_DOUBLE_EQ(muOfI(kJop, 0.0), kJop.muS);
    EXPECT_NEAR(muOfI(kJop, 1e9), kJop.muD, 1e-9);
    EXPECT_LT(muOfI(kJop, 1e3), kJop.muD);
}

TEST(MuILaw, MonotonicIncreasing) {
    double prev = muOfI(kJop, 0.0);
    for (double I = 1e-6; I < 1e3; I *= 1.3) {
        const double m = muOfI(kJop, I);
        EXPECT_GT(m, prev) << "at I = " << I;
        EXPECT_GT(dMuDI(kJop, I), 0.0);
        prev = m;
    }
}

TEST(MuILaw, HalfwayAtIEqualsI0AndScalesWithI0) {
    // mu(I0) is the midpoint between muS and muD whatever I0 is; doubling I0 doubles the I needed.
    for (double I0 : {0.05, 0.279, 1.0}) {
        const MuIParams m{0.3, 0.6, I0};
        EXPECT_NEAR(muOfI(m, I0), 0.45, 1e-14);
        const MuIParams m2{0.3, 0.6, 2 * I0};
        EXPECT_NEAR(muOfI(m2, 2 * 0.37 * I0), muOfI(m, 0.37 * I0), 1e-14);
    }
}

TEST(MuILaw, DerivativeMatchesFiniteDifference) {
    for (double I : {1e-4, 0.01, 0.3, 5.0}) {
        const double h = 1e-6 * I;
        const double fd = (muOfI(kJop, I + h) - muOfI(kJop, I - h)) / (2 * h);
        EXPECT_NEAR(dMuDI(kJop, I), fd, 1e-6 * std::abs(fd));
    }
}

TEST(MuILaw, InertialNumberDefinition) {
    // d = 0.5 mm, gammaDot = 10/s, p = 1000 Pa, rhoS = 2500: I = 5e-3 / sqrt(0.4)
    EXPECT_NEAR(inertialNumber(5e-4, 10.0, 1000.0, 2500.0), 5e-3 / std::sqrt(0.4), 1e-15);
}

TEST(MuILaw, ViscosityIsCappedAtEtaMax) {
    EXPECT_DOUBLE_EQ(granularViscosity(0.5, 1000.0, 0.0, 30.0), 30.0);
    EXPECT_DOUBLE_EQ(granularViscosity(0.5, 1000.0, 1e-6, 30.0), 30.0);
    EXPECT_NEAR(granularViscosity(0.5, 1000.0, 100.0, 30.0), 5.0, 1e-14);
}

TEST(MuILaw, RauterEtaMax) {
    // rhoS/10 sqrt(g H^3): quartz, H = 0.1 m
    EXPECT_NEAR(rauterEtaMax(2650.0, 9.81, 0.1), 265.0 * std::sqrt(9.81e-3), 1e-10);
}

TEST(WellPosedness, JopGlassBeadsWindowMatchesBarker2015) {
    // PHYSICS.md: 0.019 < I < 0.85 for (0.382, 0.643, 0.279) in the standard convention.
    const auto w = wellPosedWindow(kJop);
    ASSERT_TRUE(w.exists);
    EXPECT_NEAR(w.lower, 0.019, 0.1 * 0.019);
    EXPECT_NEAR(w.upper, 0.85, 0.1 * 0.85);
    EXPECT_LT(illPosednessIndicator(kJop, 0.1), 0.0);
    EXPECT_GT(illPosednessIndicator(kJop, 1e-4), 0.0);
    EXPECT_NEAR(illPosednessIndicator(kJop, w.lower), 0.0, 1e-9);
}

TEST(WellPosedness, AvicelWindow) {
    // PHYSICS.md: 0.020 < I < 1.4 for (0.31, 0.44, 0.28).
    const auto w = wellPosedWindow(kAvicel);
    ASSERT_TRUE(w.exists);
    EXPECT_NEAR(w.lower, 0.020, 0.1 * 0.020);
    EXPECT_NEAR(w.upper, 1.4, 0.1 * 1.4);
}

TEST(WellPosedness, PaperQuartzHasNoWindow) {
    const auto w = wellPosedWindow(kQuartzPaper);
    EXPECT_FALSE(w.exists);
    for (double I = 1e-8; I < 1e4; I *= 1.5) EXPECT_GT(illPosednessIndicator(kQuartzPaper, I), 0.0);
}

TEST(Regularised, EqualsStandardLawInTheWellPosedWindow) {
    const auto r = makeRegularisedLaw(kJop);
    const auto w = wellPosedWindow(kJop);
    ASSERT_TRUE(r.wellPosed);
    EXPECT_DOUBLE_EQ(r.IN, w.lower);
    for (double I = w.lower; I <= w.upper; I *= 1.05)
        EXPECT_DOUBLE_EQ(muRegularised(r, I), muOfI(kJop, I)) << "at I = " << I;
}

TEST(Regularised, ContinuousAtCutoffAndBelowStandardLaw) {
    const auto r = makeRegularisedLaw(kJop);
    EXPECT_NEAR(muRegularised(r, r.IN * (1 - 1e-9)), muOfI(kJop, r.IN), 1e-7);
    // Below I_N the friction decays (slowly) to zero: the static limit is not a yield stress.
    double prev = muRegularised(r, r.IN * 0.999);
    for (double I = r.IN * 0.5; I > 1e-12; I *= 0.5) {
        const double m = muRegularised(r, I);
        EXPECT_LT(m, prev);
        EXPECT_GT(m, 0.0);
        prev = m;
    }
    EXPECT_EQ(muRegularised(r, 0.0), 0.0);
}

TEST(Regularised, LowBranchIsWellPosedWhereFrictionIsLow) {
    // On the low branch nu = I mu'/mu = mu^2 / (2 alpha), and Barker & Gray's branch is well-posed
    // (C <= 0) for small enough mu; check C on the branch for the Jop law.
    const auto r = makeRegularisedLaw(kJop);
    for (double I = r.IN * 0.9; I > 1e-10; I *= 0.3) {
        const double mu = muRegularised(r, I);
        const double nu = mu * mu / (2 * r.alpha);
        EXPECT_LE(illPosednessIndicator(mu, nu), 1e-12) << "at I = " << I;
    }
}

TEST(Regularised, NoWindowJoinsAtLeastIllPosedPoint) {
    const auto r = makeRegularisedLaw(kQuartzPaper);
    EXPECT_FALSE(r.wellPosed);
    EXPECT_NEAR(r.IN, wellPosedWindow(kQuartzPaper).leastIllPosedI, 1e-15);
    EXPECT_NEAR(muRegularised(r, r.IN * (1 - 1e-9)), muOfI(kQuartzPaper, r.IN), 1e-6);
}
