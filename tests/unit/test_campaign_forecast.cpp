// SPDX-License-Identifier: GPL-3.0-or-later
// The campaign forecast on ledger rows whose flow to a verdict and cost follow known laws: the fit
// has to recover them, and a point's flow already run has to come off what is left.
#include <gtest/gtest.h>

#include <cmath>

#include "campaign/forecast.hpp"

using namespace mixload;
using namespace mixload::experiments;

namespace {

const char* kRanges = "scene = \"mixer\"\n[feed_kg_h]\nmin = 2.5\nmax = 60\nunit = \"kg/h\"\nscale = \"log\"\n"
                      "[rpm]\nmin = 39\nmax = 254\nunit = \"rpm\"\n";

store::LedgerRun row(int index, double feed, double rpm, const std::string& status) {
    store::LedgerRun r;
    r.index = index;
    r.status = status;
    r.params = {{"feed_kg_h", feed}, {"rpm", rpm}};
    if (status == "done") {
        const double m = 0.02 * std::sqrt(feed) * 100.0 / rpm;  // a smooth loading law
        const double tau = m / feed * 3600.0;
        const double t = 12.0 + 1.8 * tau;
        r.result = {{"steady", true}, {"loading_kg", m}, {"steady_time_s", t}};
        r.coreSeconds = 40.0 * t;
    }
    return r;
}

}  // namespace

TEST(CampaignForecast, RecoversTheFlowAndCostLawsAndCountsTheFlowRun) {
    store::CampaignInfo c;
    c.scene = "mixer";
    c.sceneJson = {{"kind", "mixer"}, {"mesh", "coarse"}, {"mesher", "ogrid"}, {"method", "mrf"},
                   {"numerics", "fast"}, {"scene", "gcm250-v2"}, {"steady_window_residence", 0.5}};
    const auto space = parseRanges(kRanges, "forecast.toml");
    std::vector<store::LedgerRun> runs;
    const double feeds[] = {3, 5, 9, 15, 25, 40, 55, 4, 30};
    const double rpms[] = {45, 200, 90, 150, 60, 240, 120, 170, 80};
    for (int i = 0; i < 9; ++i) runs.push_back(row(i, feeds[i], rpms[i], "done"));
    // One run continued the point's kept progress: its verdict's time counts from its own start,
    // so the laws hold only with the flow before it counted.
    const double before = 0.6 * runs[0].result["steady_time_s"].get<double>();
    runs[0].result["steady_time_s"] = runs[0].result["steady_time_s"].get<double>() - before;
    runs[0].result["start"] = {{"continues_run_dir", "0-x"}, {"source_time_s", 1.0}, {"flow_before_s", before}};
    runs.push_back(row(9, 10, 100, "running"));
    runs.push_back(row(10, 20, 130, "queued"));
    runs.push_back(row(11, 58, 250, "queued"));  // shorter residence than any finished run

    // Fewer than five steady runs: no fit to trust.
    EXPECT_TRUE(forecastCampaign(c, std::vector<store::LedgerRun>(runs.begin(), runs.begin() + 4), space, {}, {}).is_null());
    EXPECT_FALSE(fitRunCost(c, std::vector<store::LedgerRun>(runs.begin(), runs.begin() + 4), {}));

    // The cost model alone (what adaptive points are weighed by): a point of 0.1 kg at 2 kg/h has a
    // residence time of 180 s, so 12 + 1.8 * 180 s of flow at 40 core-s each; flow already run comes
    // off, but never below half a residence time.
    const auto cost = fitRunCost(c, runs, {});
    ASSERT_TRUE(cost);
    EXPECT_EQ(cost->runs, 9u);
    EXPECT_NEAR(cost->coreHours(0.1, 2.0), (12.0 + 1.8 * 180.0) * 40.0 / 3600.0, 1e-9);
    EXPECT_NEAR(cost->coreHours(0.1, 2.0, 200.0), (12.0 + 1.8 * 180.0 - 200.0) * 40.0 / 3600.0, 1e-9);
    EXPECT_NEAR(cost->coreHours(0.1, 2.0, 1000.0), 90.0 * 40.0 / 3600.0, 1e-9);

    const auto f = forecastCampaign(c, runs, space, {}, {{9, 30.0}});
    ASSERT_TRUE(f.is_object());
    EXPECT_NEAR(f["flow_fit"]["intercept_s"].get<double>(), 12.0, 1e-6);
    EXPECT_NEAR(f["flow_fit"]["per_residence_time"].get<double>(), 1.8, 1e-9);
    EXPECT_NEAR(f["core_seconds_per_flow_second"].get<double>(), 40.0, 1e-9);
    ASSERT_EQ(f["points"].size(), 3u);
    // No point is forecast faster than the fastest verdict among the finished runs.
    double fastest = 1e300;
    for (int i = 1; i < 9; ++i) fastest = std::min(fastest, runs[static_cast<size_t>(i)].result["steady_time_s"].get<double>());
    EXPECT_NEAR(f["flow_fit"]["floor_s"].get<double>(), fastest, 1e-9);
    EXPECT_NEAR(f["points"][2]["flow_to_verdict_s"].get<double>(), fastest, 1e-9);
    double sum = 0;
    for (const auto& p : f["points"]) {
        const double m = p["predicted_loading_kg"].get<double>(), feed = p["feed_kg_h"].get<double>();
        const double tau = m / feed * 3600.0, flow = std::max(12.0 + 1.8 * tau, fastest), done = p["flow_done_s"].get<double>();
        EXPECT_NEAR(p["flow_to_verdict_s"].get<double>(), flow, 1e-6 * flow);
        EXPECT_NEAR(p["core_hours_left"].get<double>(), std::max(flow - done, 0.5 * tau) * 40.0 / 3600.0, 1e-9);
        EXPECT_LE(p["core_hours_left_90"][0].get<double>(), p["core_hours_left"].get<double>());
        EXPECT_GE(p["core_hours_left_90"][1].get<double>(), p["core_hours_left"].get<double>());
        sum += p["core_hours_left"].get<double>();
    }
    EXPECT_EQ(f["points"][0]["flow_done_s"].get<double>(), 30.0);
    EXPECT_EQ(f["points"][1]["flow_done_s"].get<double>(), 0.0);
    EXPECT_NEAR(f["core_hours_left"].get<double>(), sum, 1e-12);
    // The loading model interpolates a smooth law between its runs.
    const double truth = 0.02 * std::sqrt(10.0) * 100.0 / 100.0;
    EXPECT_NEAR(f["points"][0]["predicted_loading_kg"].get<double>(), truth, 0.15 * truth);
}
