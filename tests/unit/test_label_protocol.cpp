// SPDX-License-Identifier: GPL-3.0-or-later
// The label protocol's level history (fullcfd/post/level_history) and its start and windows
// (fullcfd/run/label_protocol), on histories made here whose answers are known.
#include <gtest/gtest.h>

#include <cmath>

#include "common/input_error.hpp"
#include "post/level_history.hpp"
#include "run/label_protocol.hpp"

using mixload::post::levelHistory;

namespace {
// Samples every 0.1 s of f over [0, end].
template <class F>
void sample(double end, F f, std::vector<double>& t, std::vector<double>& M) {
    for (double x = 0; x <= end + 1e-9; x += 0.1) t.push_back(x), M.push_back(f(x));
}
}  // namespace

TEST(LabelProtocol, AFillThatSettlesOnceSeesNoLevelChange) {
    // Filling from 0.05 kg towards 0.2 kg with a 10 s time constant; feed 0.01 kg/s: residence 20 s.
    std::vector<double> t, M;
    sample(120, [](double x) { return 0.2 - 0.15 * std::exp(-x / 10); }, t, M);
    const auto h = levelHistory(t, M, 0.01, 20, 1.0, 0.05);
    EXPECT_FALSE(h.levelChangeSeen);
    EXPECT_NEAR(h.finalLevel, 0.2, 1e-4);
    EXPECT_NEAR(h.residenceTime, 20, 0.01);
    // Inside 5% of 0.2 kg once 0.15 exp(-t/10) < 0.01, t > 27.1 s, plus half the 1 s smoothing.
    EXPECT_NEAR(h.settledAt, 27.6, 0.3);
    EXPECT_NEAR(h.settledResidenceTimes, (120 - 27.6) / 20, 0.02);
}

TEST(LabelProtocol, APlateauThatSurgesIsALevelChange) {
    // The reference point's shape: up to a 0.395 kg plateau, held, then down to 0.331 kg.
    std::vector<double> t, M;
    sample(400, [](double x) { return x < 150 ? 0.395 - 0.075 * std::exp(-x / 20) : 0.331 + 0.064 * std::exp(-(x - 150) / 15); }, t, M);
    const auto h = levelHistory(t, M, 0.331 / 240, 60, 3.0, 0.05);
    // The fill passes through 0.331 +- 5% on its way up, then leaves for the plateau.
    EXPECT_TRUE(h.levelChangeSeen);
    EXPECT_GT(h.settledAt, 150);
    EXPECT_LT(h.settledResidenceTimes, 1.0);  // 400 s minus ~165 s, over 240 s
}

TEST(LabelProtocol, APaddlesRippleIsNoChangeOfLevel) {
    // +-8% at the revolution (1 s), about a steady 0.1 kg: smoothed over one revolution, no change.
    std::vector<double> t, M;
    sample(60, [](double x) { return 0.1 * (1 + 0.08 * std::sin(2 * M_PI * x)); }, t, M);
    const auto h = levelHistory(t, M, 0.01, 10, 1.0, 0.05);
    EXPECT_FALSE(h.levelChangeSeen);
    EXPECT_NEAR(h.settledAt, 0, 1e-9);
    EXPECT_NEAR(h.settledResidenceTimes, 6, 0.05);
}

TEST(LabelProtocol, SetsItsStartAndWindowsAndRefusesOthers) {
    mixload::scene::MixerOverrides m;
    mixload::run::applyLabelProtocol(m);
    EXPECT_EQ(*m.initialLoadingKg, mixload::run::kLabelDepositKg);
    EXPECT_EQ(*m.residence, mixload::run::kLabelWindowResidence);
    EXPECT_EQ(*m.endTime, mixload::run::kLabelEndTimeS);
    EXPECT_TRUE(mixload::run::keepsLabelProtocol(m.build()));
    mixload::scene::MixerOverrides own;
    own.initialLoadingKg = 0.3;
    EXPECT_THROW(mixload::run::applyLabelProtocol(own), mixload::InputError);
    mixload::scene::MixerOverrides scene;  // the scene file's deposit and windows
    EXPECT_FALSE(mixload::run::keepsLabelProtocol(scene.build()));
}
