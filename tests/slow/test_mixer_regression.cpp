// SPDX-License-Identifier: GPL-3.0-or-later
// Regression of the steady loading (label slow: about 20 and 40 minutes on one core). The current setup
// (numerics preset `fast`) must give, at three points of the 1 cm O-grid started from the 0.03 kg
// deposit, the reference loadings within 1%, and a run started warm from another point's field
// must reach the cold run's loading within 1%.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "../cfd/cli_harness.hpp"

using namespace mixload::testing;
namespace fs = std::filesystem;

namespace {
// Reference loadings, measured on 2026-11-29 with `mixload mixer --scene gcm250 --cell-size 0.01
// --initial-loading-kg 0.03 --steady-tol 0.01 --steady-flow-tol 0.03 --rpm R --feed-kg-h F`
// (README, "Cost of a steady point"; docs/studies/mixer-cost): at 39 rpm, 5 kg/h the legacy
// settings' value (the current ones gave +0.27%); at 45 kg/h the current settings' values, because
// the legacy runs were called steady on a plateau (0.0901 and 0.0345 kg) that runs differing from
// them by round-off left, rising by 5-10%. gcm250's 1 cm mesh is cell for cell the test scene
// gcm250-1cm's (its paddles as that mesh cut them, 14.1 mm), which these runs now use.
struct Point {
    double rpm, feed, referenceKg;
};
constexpr Point kPoints[] = {{39, 5, 0.024087}, {39, 45, 0.09921}, {254, 45, 0.03626}};

nlohmann::json run(const fs::path& out, const Point& p, const std::string& warmFrom = "") {
    std::vector<std::string> args{"mixer", "--scene", kGcm250At1cm, "--cell-size", "0.01", "--initial-loading-kg", "0.03",
                                  "--steady-tol", "0.01", "--steady-flow-tol", "0.03", "--rpm",
                                  std::to_string(p.rpm), "--feed-kg-h", std::to_string(p.feed),
                                  "--out", out.string(), "--json"};
    if (!warmFrom.empty()) args.insert(args.end(), {"--warm-from", warmFrom});
    const auto r = runMixload(args);
    EXPECT_EQ(r.rc, 0) << r.err;
    return r.rc == 0 ? nlohmann::json::parse(r.out) : nlohmann::json{};
}


// The cold runs, made once per process (ctest runs each test in a process of its own, so the warm
// test makes them again: about 20 minutes on one core).
const std::vector<nlohmann::json>& coldRuns() {
    static const std::vector<nlohmann::json> cold = [] {
        const fs::path dir = scratchDir("mixer-regression-cold");
        std::vector<nlohmann::json> r;
        for (const auto& p : kPoints) r.push_back(run(dir / ("cold-" + std::to_string(r.size())), p));
        return r;
    }();
    return cold;
}
}  // namespace

TEST(MixerRegression, CurrentSetupKeepsTheLoading) {
    const auto& cold = coldRuns();
    for (size_t i = 0; i < cold.size(); ++i) {
        const auto& r = cold[i];
        const auto& p = kPoints[i];
        ASSERT_FALSE(r.is_null());
        EXPECT_TRUE(r["steady"].get<bool>());
        EXPECT_TRUE(r["powder_balance_ok"].get<bool>());
        EXPECT_NEAR(r["loading_kg"].get<double>(), p.referenceKg, 0.01 * p.referenceKg)
            << p.rpm << " rpm, " << p.feed << " kg/h";
    }
}

// Warm from the previous point (the first from the last): within the steady tolerance. Fails as
// measured on 2026-11-29 (issue 13, blocked): 39 rpm, 5 kg/h started from the 254 rpm, 45 kg/h
// field settles at 0.0173 kg, 28% below the cold run, because a start without a resolved bed ends
// in another state of this scene. Kept as the requirement a warm start has to meet.
TEST(MixerRegression, WarmStartsReachTheColdLoading) {
    const auto& cold = coldRuns();
    const fs::path dir = scratchDir("mixer-regression-warm");
    for (size_t i = 0; i < cold.size(); ++i) {
        ASSERT_FALSE(cold[i].is_null());
        const size_t from = (i + cold.size() - 1) % cold.size();
        const auto w = run(dir / ("warm-" + std::to_string(i)), kPoints[i],
                           cold[from]["run_dir"].get<std::string>());
        ASSERT_FALSE(w.is_null());
        EXPECT_TRUE(w["steady"].get<bool>());
        const double m = cold[i]["loading_kg"].get<double>();
        EXPECT_NEAR(w["loading_kg"].get<double>(), m, 0.01 * m) << "warm at point " << i;
    }
}
