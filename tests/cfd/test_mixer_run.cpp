// SPDX-License-Identifier: GPL-3.0-or-later
// Tiny real mixer runs (gcm250 on a 1 cm background mesh, about 8k cells) through interFoam with
// mixload's rheology and loading monitor: powder balance, an active MRF zone, a resting bed, and
// bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <numbers>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

using namespace mixload::testing;
namespace fs = std::filesystem;

namespace {
nlohmann::json runMixer(const std::string& name, std::vector<std::string> args) {
    const fs::path out = scratchDir("mixer-" + name) / "run";
    std::vector<std::string> all{"mixer", "--cell-size", "0.01", "--out", out.string(), "--json"};
    all.insert(all.end(), args.begin(), args.end());
    const auto r = runMixload(all);
    EXPECT_EQ(r.rc, 0) << r.err;
    return r.rc == 0 ? nlohmann::json::parse(r.out) : nlohmann::json{};
}

void expectRejected(std::vector<std::string> args, const std::string& needle) {
    mixload::testing::expectRejected("mixer", std::move(args), needle);
}

fs::path writeScene(const std::string& name, const std::string& text) {
    const fs::path f = scratchDir("mixer-scenes") / (name + ".toml");
    std::ofstream(f) << text;
    return f;
}
}  // namespace

TEST(MixerRun, MrfReportsEveryFieldAndBalancesPowder) {
    const auto r = runMixer("mrf", {"--method", "mrf", "--end-time", "0.05"});
    ASSERT_FALSE(r.is_null());
    for (const char* k : {"loading_kg", "loading_std_kg", "steady", "steady_time_s", "outflow_kg_h",
                          "history", "cells", "wall_seconds", "core_seconds", "method"})
        EXPECT_TRUE(r.contains(k)) << k;
    EXPECT_EQ(r["method"], "mrf");
    EXPECT_GT(r["cells"].get<long>(), 1000);
    EXPECT_TRUE(fs::exists(r["plot"].get<std::string>()));
    // fed - out - (M_end - M_0) within 1% of the fed mass (here the bed also drains: compare with
    // the larger of fed and discharged mass).
    const double fed = r["fed_kg"], out = r["out_kg"];
    const double gained = r["final_loading_kg"].get<double>() - r["initial_loading_kg"].get<double>();
    EXPECT_GT(fed, 0);
    EXPECT_LT(std::abs(fed - out - gained), 0.01 * fed);
    EXPECT_NEAR(r["initial_loading_kg"].get<double>(), 0.3, 0.1);  // staircase cells: not exact
}

TEST(MixerRun, MrfZoneDrivesThePowderAtTipSpeed) {
    // 254 rpm: paddle tips at 0.047 m move at 1.25 m/s; the draining bed alone moves ~0.3 m/s.
    const auto r = runMixer("mrf-fast", {"--rpm", "254", "--end-time", "0.05"});
    ASSERT_FALSE(r.is_null());
    const double tip = 254 * 2 * std::numbers::pi / 60 * 0.047;
    EXPECT_GT(r["max_powder_speed_m_s"].get<double>(), 0.6 * tip);
    EXPECT_LT(r["max_powder_speed_m_s"].get<double>(), 1.5 * tip);
}

TEST(MixerRun, RestingBedStaysAtRest) {
    // No rotation, no feed, the discharge above the bed (weir chord near horizontal, closing the
    // lower half): 300 time steps, every powder cell slower than 2 cm/s.
    const auto scene = writeScene("rest", "[weir]\nchord_angle_deg = 85\ncovers = \"+y\"\n"
                                          "[operation]\nrpm = 0\nfeed_kg_h = 0\n"
                                          "initial_loading_kg = 0.3\n");
    const auto r = runMixer("rest", {"--scene", scene.string(), "--end-time", "1"});
    ASSERT_FALSE(r.is_null());
    EXPECT_LT(r["max_powder_speed_m_s"].get<double>(), 0.02);
    EXPECT_LT(std::abs(r["final_loading_kg"].get<double>() - r["initial_loading_kg"].get<double>()),
              1e-6);
}

TEST(MixerCliErrors, BadFlagsAndScenes) {
    expectRejected({"--method", "frozen"}, "invalid method = frozen: allowed mrf|lts|sm");
    expectRejected({"--feed-kg-h", "-5"}, "invalid feed-kg-h = -5");
    expectRejected({"--mesh", "huge"}, "invalid mesh = huge: allowed coarse|medium|fine");
    expectRejected({"--mu-s", "0.5", "--mu-d", "0.4"}, "invalid mu_d = 0.4");
    expectRejected({"--scene", "nosuch"}, "invalid scene = nosuch");
    const auto longPaddle = writeScene("long", "[impeller]\npaddle_tip_clearance_m = -0.002\n");
    expectRejected({"--scene", longPaddle.string()}, "impeller.paddle_tip_clearance_m");
    const auto weir = writeScene("weir", "[weir]\nchord_angle_deg = 120\n");
    expectRejected({"--scene", weir.string()}, "invalid weir.chord_angle_deg = 120");
}
