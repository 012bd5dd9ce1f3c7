// SPDX-License-Identifier: GPL-3.0-or-later
// The calibration fit on cheap analytic responses: it reaches the band in a few evaluations, stops
// there, stays inside the bounds, reports a target it cannot reach, and is deterministic (the
// property the mixer calibration's resume rests on).
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "calibrate/calibrator.hpp"
#include "bench/pareto.hpp"
#include "calibrate/mixer_calibration.hpp"
#include "studies/formulation_study.hpp"
#include "studies/methods_comparison.hpp"
#include "common/input_error.hpp"

using namespace mixload::experiments;

namespace {
// A dam-like response: loading rises steeply with the weir angle (as the probes showed).
double loading(double deg) { return 0.03 + 0.30 * std::pow((deg - 20) / 70.0, 2.5); }
std::vector<double> residual(double m, double target, double tol) { return {(m - target) / (tol * target)}; }
}  // namespace

TEST(Calibrator, OneParameterReachesTheBandInAFewEvaluations) {
    const std::vector<CalibrationBound> b{{"weir.chord_angle_deg", 20, 89, 55}};
    const auto t = calibrate(
        b, [](const std::vector<double>& x) { return residual(loading(x[0]), 0.25, 0.12); }, {});
    EXPECT_EQ(t.stop, "within-stop-rms");
    EXPECT_LE(t.x.size(), 10u);
    EXPECT_LE(std::abs(t.r[t.best][0]), 0.25);
    for (const auto& x : t.x) {
        EXPECT_GE(x[0], 20);
        EXPECT_LE(x[0], 89);
    }
}

TEST(Calibrator, OneParameterOneTargetIsARootSearchOfAFewEvaluations) {
    const std::vector<CalibrationBound> b{{"barrel.bore_m", 0.10, 0.20, 0.14}};
    // A dam-like loading that grows with the bore; targets on both sides of the start.
    for (double target : {0.2, 0.311, 0.45}) {
        int calls = 0;
        const auto t = calibrate(
            b,
            [&](const std::vector<double>& x) {
                ++calls;
                return residual(0.244 * std::pow(x[0] / 0.14, 2.6), target, 0.12);
            },
            {.stopRms = 0.25, .residuals = 1});
        EXPECT_EQ(t.stop, "within-stop-rms") << target;
        EXPECT_LE(t.x.size(), 5u) << target;
        EXPECT_EQ(calls, static_cast<int>(t.x.size())) << "every evaluation once";
        EXPECT_LE(std::abs(t.r[t.best][0]), 0.25);
    }
    // Beyond the range: it stops at the bound and says so.
    const auto far = calibrate(
        b, [](const std::vector<double>& x) { return residual(0.244 * std::pow(x[0] / 0.14, 2.6), 5.0, 0.12); },
        {.residuals = 1});
    EXPECT_EQ(far.stop, "bound");
    EXPECT_DOUBLE_EQ(far.x[far.best][0], 0.20);
}

TEST(Calibrator, TwoTargetsTwoParameters) {
    // M = a * feed / rpm + b: two operating points fix both.
    const std::vector<CalibrationBound> b{{"a", 0.5, 20, 5}, {"b", 0.0, 0.5, 0.1}};
    const auto t = calibrate(
        b,
        [](const std::vector<double>& x) {
            const double m1 = x[0] * 5 / 39 + x[1], m2 = x[0] * 45 / 254 + x[1];
            return std::vector<double>{(m1 - 0.311) / (0.05 * 0.311), (m2 - 0.35) / (0.05 * 0.35)};
        },
        {.maxEvals = 30});
    EXPECT_EQ(t.stop, "within-stop-rms");
    EXPECT_LE(t.rms[t.best], 0.25);
}

TEST(Calibrator, AnUnreachableTargetEndsAtTheBoundWithItsResidual) {
    const std::vector<CalibrationBound> b{{"weir.chord_angle_deg", 20, 89, 55}};
    const auto t = calibrate(
        b, [](const std::vector<double>& x) { return residual(loading(x[0]), 1.0, 0.12); },
        {.maxEvals = 8});
    EXPECT_NE(t.stop, "within-stop-rms");
    EXPECT_NEAR(t.x[t.best][0], 89, 1.0);
    EXPECT_LT(t.r[t.best][0], -1);  // still below the band: the report says by how much
}

TEST(Calibrator, IsDeterministicAndPassesErrorsOn) {
    const std::vector<CalibrationBound> b{{"k", 20, 89, 55}};
    const auto f = [](const std::vector<double>& x) { return residual(loading(x[0]), 0.2, 0.12); };
    const auto t1 = calibrate(b, f, {}), t2 = calibrate(b, f, {});
    EXPECT_EQ(t1.x, t2.x);
    int calls = 0;
    size_t seen = 0;
    EXPECT_THROW(calibrate(
                     b,
                     [&](const std::vector<double>& x) {
                         if (++calls == 2) throw std::runtime_error("run failed");
                         return f(x);
                     },
                     {}, [&](const CalibrationTrace& t) { seen = t.x.size(); }),
                 std::runtime_error);
    EXPECT_EQ(seen, 1u);
}

TEST(Calibrator, TheDepositFollowsTheEvaluationsSoFar) {
    const std::vector<CalibrationBound> b{{"barrel.bore_m", 0.10, 0.20, 0.14}};
    const std::vector<std::vector<double>> xs{{0.14}, {0.165}};
    const std::vector<double> m{0.244, 0.39};
    EXPECT_FALSE(depositFor({{0.14}}, {0.244}, {0.15}, b));  // one evaluation: the scene's deposit
    EXPECT_DOUBLE_EQ(*depositFor(xs, m, {0.152}, b), 0.314);  // between: interpolated, 3 digits
    EXPECT_DOUBLE_EQ(*depositFor(xs, m, {0.19}, b), 0.536);   // beyond: extrapolated
    EXPECT_DOUBLE_EQ(*depositFor(xs, m, {0.10}, b), 0.0104);  // below: extrapolated too
    EXPECT_DOUBLE_EQ(*depositFor(xs, m, {0.05}, b), 0.244);   // never negative: the smallest loading
    // Two parameters: the nearest evaluation's loading.
    const std::vector<CalibrationBound> b2{{"a", 0, 1, 0.5}, {"b", 0, 10, 5}};
    EXPECT_DOUBLE_EQ(*depositFor({{0.1, 1}, {0.9, 9}}, {0.2, 0.4}, {0.8, 8}, b2), 0.4);
}

TEST(Calibrator, ALogScaledParameterSearchesInFactors) {
    // A viscosity cap spanning four decades; the response is linear in log(x): a log search finds
    // the root in a handful of evaluations, and every point stays inside the bounds.
    const CalibrationBound b = parseCalibrationParam("cap_h_ratio=1:10000:log", false);
    EXPECT_TRUE(b.log);
    EXPECT_DOUBLE_EQ(b.start, 100.0);  // the geometric middle
    const auto t = calibrate(
        {b}, [](const std::vector<double>& x) { return std::vector<double>{(std::log10(x[0]) - 2.6) / 0.05}; }, {});
    EXPECT_EQ(t.stop, "within-stop-rms");
    EXPECT_LE(t.x.size(), 6u);
    EXPECT_NEAR(std::log10(t.x[t.best][0]), 2.6, 0.05 * 0.25 + 1e-12);
    for (const auto& x : t.x) {
        EXPECT_GE(x[0], 1.0);
        EXPECT_LE(x[0], 10000.0);
    }
}

TEST(Calibrator, ParamTextIsCheckedField) {
    EXPECT_THROW(parseCalibrationParam("mu_s=0.3:0.6"), mixload::InputError);  // the mixer wants TABLE.KEY
    EXPECT_NO_THROW(parseCalibrationParam("mu_s=0.3:0.6", false));
    EXPECT_THROW(parseCalibrationParam("mu_s=0:10:log", false), mixload::InputError);  // log needs LO > 0
    EXPECT_THROW(parseCalibrationParam("mu_s=0.6:0.3", false), mixload::InputError);
    EXPECT_THROW(parseCalibrationParam("mu_s=0.3:0.6:0.9", false), mixload::InputError);  // start outside
    const auto b = parseCalibrationParam("i0=0.1:0.5:0.2", false);
    EXPECT_FALSE(b.log);
    EXPECT_DOUBLE_EQ(b.start, 0.2);
}

TEST(ParetoFront, KeepsOnlyMethodsNoOtherBeatsOnBoth) {
    std::vector<ParetoMethod> ms{{"reference", 10, 0},   {"coarse", 2, 0.05}, {"slow and bad", 5, 0.2},
                                 {"fast", 1e-6, 0.1},     {"tie", 2, 0.05}};
    markParetoFront(ms);
    EXPECT_TRUE(ms[0].front);   // zero error
    EXPECT_TRUE(ms[1].front);   // tied with "tie": neither beats the other
    EXPECT_FALSE(ms[2].front);  // coarse is faster and better
    EXPECT_TRUE(ms[3].front);   // fastest
    EXPECT_TRUE(ms[4].front);
}

TEST(Fig7, FitsOneLinePerParameterThroughTheReference) {
    // mu_s at 0.8 and 1.2 with M falling as mu_s rises (this model's finding), I0 with M falling as
    // I0 rises (the paper's sign), d not steady yet, a two-parameter what-if ignored.
    const nlohmann::json rows = nlohmann::json::array({
        {{"factors", {{"mu_s", 0.8}}}, {"sign_paper", -1}, {"change_model", 0.079}},
        {{"factors", {{"mu_s", 1.2}}}, {"sign_paper", 1}, {"change_model", -0.095}},
        {{"factors", {{"i0", 1.2}}}, {"sign_paper", -1}, {"change_model", -0.05}},
        {{"factors", {{"d", 0.8}}}, {"sign_paper", -1}},
        {{"factors", {{"rho", 1.5}, {"mu_s", 0.9}}}, {"sign_paper", 1}, {"change_model", 0.5}},
    });
    const auto p = mixload::experiments::fig7Fit(rows);
    ASSERT_EQ(p.size(), 2u);
    EXPECT_EQ(p[0]["parameter"], "mu_s");
    EXPECT_EQ(p[0]["steady_runs"], 2);
    // Least squares through (0.8, 1.079), (1, 1), (1.2, 0.905): slope (0.905 - 1.079) / 0.4.
    EXPECT_NEAR(p[0]["slope"].get<double>(), (0.905 - 1.079) / 0.4, 1e-12);
    EXPECT_EQ(p[0]["sign_paper"], 1);
    EXPECT_EQ(p[0]["verdict"], "opposite sign");
    EXPECT_EQ(p[1]["parameter"], "i0");
    EXPECT_NEAR(p[1]["slope"].get<double>(), -0.25, 1e-12);
    EXPECT_EQ(p[1]["verdict"], "same sign");
    EXPECT_FALSE(p[1].contains("from"));
}

TEST(Fig7, WithoutItsOwnRunsI0MirrorsTheDRuns) {
    // d x 0.8 and x 1.25 steady, no I0 run: I0's panel is the d runs at 1/f (1.25 and 0.8), placed
    // before d, with the paper's sign for I0 (falls).
    const nlohmann::json rows = nlohmann::json::array({
        {{"factors", {{"d", 0.8}}}, {"sign_paper", -1}, {"change_model", -0.1}},
        {{"factors", {{"d", 1.25}}}, {"sign_paper", 1}, {"change_model", 0.05}},
    });
    const auto p = mixload::experiments::fig7Fit(rows);
    ASSERT_EQ(p.size(), 2u);
    EXPECT_EQ(p[0]["parameter"], "i0");
    EXPECT_EQ(p[1]["parameter"], "d");
    EXPECT_TRUE(p[0].contains("from"));
    EXPECT_EQ(p[0]["steady_runs"], 2);
    EXPECT_NEAR(p[0]["points"][1][0].get<double>(), 1.25, 1e-12);
    EXPECT_NEAR(p[0]["points"][1][1].get<double>(), 0.9, 1e-12);
    EXPECT_LT(p[0]["slope"].get<double>(), 0);
    EXPECT_GT(p[1]["slope"].get<double>(), 0);
    EXPECT_EQ(p[0]["verdict"], "same sign");
    // The presets: fig7 runs 30 variants, fig7-similar the 24 without I0.
    EXPECT_EQ(mixload::experiments::formulationPreset("fig7").size(), 30u);
    const auto similar = mixload::experiments::formulationPreset("fig7-similar");
    EXPECT_EQ(similar.size(), 24u);
    for (const auto& v : similar) EXPECT_FALSE(v.factors.count("i0")) << v.name;
    // On the calibrated scene mu_d x 0.7 (0.308) falls below mu_s (0.31): that one variant is left
    // out with its reason, the other 23 run.
    std::vector<std::pair<std::string, std::string>> skipped;
    const auto valid = mixload::experiments::formulationPreset("fig7-similar", mixload::scene::loadMixerScene("gcm250-v2"), skipped);
    EXPECT_EQ(valid.size(), 23u);
    ASSERT_EQ(skipped.size(), 1u);
    EXPECT_EQ(skipped[0].first, "mu_d-30");
    EXPECT_NE(skipped[0].second.find("mu_d"), std::string::npos) << skipped[0].second;
}

TEST(MethodsComparison, ChargesAContinuedRunOnlyItsOwnSeconds) {
    // An SM run that continued the next higher feed's run at 126 s and ran to 244 s in 9 000 s of
    // wall: 76 s of wall per simulated second, not 37 (its end time over all of it). A result
    // written before start_time_s was recorded falls back to its history's first time.
    nlohmann::json mrf{{"method", "mrf"}, {"mesh", "0.02 m"}, {"rpm", 39.0}, {"feed_kg_h", 30.0},
                       {"initial_loading_kg", 0.32}, {"loading_kg", 0.5}, {"steady", true},
                       {"wall_seconds", 900.0}, {"end_time_s", 100.0}, {"start_time_s", 0.0}};
    nlohmann::json sm{{"method", "sm"}, {"mesh", "0.02 m"}, {"rpm", 39.0}, {"feed_kg_h", 30.0},
                      {"initial_loading_kg", 0.32}, {"loading_kg", 0.85}, {"steady", true}, {"start", "sm"},
                      {"wall_seconds", 9000.0}, {"end_time_s", 244.0}, {"start_time_s", 126.0}};
    auto p = compareMethods(nlohmann::json::array({mrf, sm}));
    ASSERT_EQ(p.size(), 1u);
    EXPECT_NEAR(p[0]["sm_cost"]["wall_per_simulated_s"].get<double>(), 9000.0 / 118.0, 1e-9);
    EXPECT_NEAR(p[0]["mrf_cost"]["wall_per_simulated_s"].get<double>(), 9.0, 1e-12);
    EXPECT_EQ(p[0]["sm_start"], "sm");
    sm.erase("start_time_s");
    sm["history"] = nlohmann::json::array({nlohmann::json::array({126.0, 0.92}), nlohmann::json::array({244.0, 0.85})});
    p = compareMethods(nlohmann::json::array({mrf, sm}));
    EXPECT_NEAR(p[0]["sm_cost"]["wall_per_simulated_s"].get<double>(), 9000.0 / 118.0, 1e-9);
}

TEST(MethodsComparison, PairsMrfWithSmAtTheSamePointOnly) {
    // Two points with both methods (one of them not steady), one with mrf alone: two entries, the
    // difference relative to SM, the paper's band checked, costs per simulated second.
    const auto row = [](const char* m, double feed, double M, bool steady, double wall, double sim) {
        return nlohmann::json{{"method", m}, {"mesh", "0.02 m"}, {"rpm", 39.0}, {"feed_kg_h", feed},
                              {"initial_loading_kg", 0.3}, {"loading_kg", M}, {"steady", steady},
                              {"powder_balance_ok", true}, {"wall_seconds", wall}, {"end_time_s", sim}};
    };
    const nlohmann::json rows = {row("mrf", 5, 0.84, true, 100, 50), row("sm", 5, 1.0, true, 600, 50),
                                 row("mrf", 15, 0.5, true, 80, 40), row("sm", 15, 0.5, false, 900, 30),
                                 row("mrf", 30, 0.4, true, 70, 40)};
    const auto p = mixload::experiments::compareMethods(rows);
    ASSERT_EQ(p.size(), 2u);
    EXPECT_DOUBLE_EQ(p[0]["feed_kg_h"].get<double>(), 5.0);
    EXPECT_NEAR(p[0]["mrf_below_sm_percent"].get<double>(), -16.0, 1e-12);
    EXPECT_TRUE(p[0]["in_paper_band"].get<bool>());
    EXPECT_TRUE(p[0]["both_results"].get<bool>());
    EXPECT_DOUBLE_EQ(p[0]["sm_cost"]["wall_per_simulated_s"].get<double>(), 12.0);
    EXPECT_NEAR(p[1]["mrf_below_sm_percent"].get<double>(), 0.0, 1e-12);
    EXPECT_FALSE(p[1]["in_paper_band"].get<bool>());
    EXPECT_FALSE(p[1]["both_results"].get<bool>());
}
