// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload calibrate mixer` on tiny real runs (1 cm O-grid, 0.05-0.5 s of flow): the fit reaches
// a target the solver can reach, a second call replays the ledger without running anything again,
// an evaluation stopped mid-run resumes from its run directory, and bad input is refused before
// anything is written.
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

using namespace mixload::testing;
namespace fs = std::filesystem;

namespace {
// The fitted key is the deposit: over 0.05 s the loading is the deposit (as the staircase mesh
// resolves it), a response the solver reaches in a few evaluations.
std::vector<std::string> tinyArgs(const fs::path& dir, const std::string& maxEvals) {
    return {"calibrate", "mixer", "--name", "tiny", "--dir", dir.string(), "--cell-size", "0.01",
            "--end-time", "0.05", "--allow-unsteady", "--param", "operation.initial_loading_kg=0.1:0.4",
            "--target", "39:5:0.2", "--max-evals", maxEvals, "--json", "--scene", "gcm250"};
}

nlohmann::json parsed(const CliResult& r) {
    EXPECT_TRUE(r.rc == 0 || r.rc == 1) << r.err;
    return r.out.empty() ? nlohmann::json{} : nlohmann::json::parse(r.out);
}
}  // namespace

TEST(CalibrateCli, ReachesATargetAndReplaysItsLedger) {
    const fs::path dir = scratchDir("calibrate-tiny");
    // Two evaluations are not enough: the fit stops outside the band (exit 1) with its report.
    const auto first = parsed(runMixload(tinyArgs(dir, "2")));
    ASSERT_FALSE(first.is_null());
    EXPECT_EQ(first["evaluations"].size(), 2u);
    EXPECT_EQ(first["runs_new"], 2);
    EXPECT_EQ(first["stop"], "max-evals");
    for (const char* f : {"calibration.md", "calibration.csv", "calibration.json", "calibration.png"})
        EXPECT_TRUE(fs::exists(dir / "tiny" / "report" / f)) << f;
    // More evaluations: the first two come from the ledger, the fit goes on to the band.
    const auto r = runMixload(tinyArgs(dir, "8"));
    EXPECT_EQ(r.rc, 0) << r.err;
    const auto second = parsed(r);
    ASSERT_FALSE(second.is_null());
    EXPECT_EQ(second["status"], "within-band");
    EXPECT_EQ(second["runs_reused"], 2);
    EXPECT_EQ(second["runs_new"].get<int>() + 2, static_cast<int>(second["evaluations"].size()));
    EXPECT_EQ(second["evaluations"][0]["runs"][0]["loading_kg"], first["evaluations"][0]["runs"][0]["loading_kg"]);
    EXPECT_TRUE(second["evaluations"][1]["runs"][0]["reused"].get<bool>());
    const auto& best = second["best"]["runs"][0];
    EXPECT_LE(std::abs(best["loading_kg"].get<double>() - 0.2), 0.12 * 0.2);
    // The report names the best point and its run.
    std::ifstream md(dir / "tiny" / "report" / "calibration.md");
    const std::string text((std::istreambuf_iterator<char>(md)), {});
    EXPECT_NE(text.find("within-band"), std::string::npos);
    EXPECT_TRUE(fs::exists(best["run_dir"].get<std::string>()));
}

TEST(CalibrateCli, AnEvaluationStoppedMidRunResumes) {
    const fs::path dir = scratchDir("calibrate-resume");
    auto args = tinyArgs(dir, "1");
    args[9] = "0.5";  // --end-time: long enough to be stopped mid-run
    auto stopped = args;
    stopped.insert(stopped.end(), {"--max-hours", "0.0008"});  // about 3 s
    const auto a = runMixload(stopped);
    EXPECT_EQ(a.rc, 0) << a.err;
    const auto first = nlohmann::json::parse(a.out);
    EXPECT_EQ(first["status"], "stopped-at-max-hours");
    EXPECT_EQ(first["evaluations"].size(), 0u);
    const auto b = parsed(runMixload(args));
    ASSERT_EQ(b["evaluations"].size(), 1u);
    const auto& run = b["evaluations"][0]["runs"][0];
    EXPECT_EQ(b["runs_new"], 1);
    const auto result = nlohmann::json::parse(std::ifstream(fs::path(run["run_dir"].get<std::string>()) / "result.json"));
    EXPECT_TRUE(result["resumed"].get<bool>());
    EXPECT_GE(result["end_time_s"].get<double>(), 0.5 - 1e-6);
}

TEST(CalibrateCli, SizedDepositsFollowTheEvaluationsSoFar) {
    // Over 0.05 s the loading is the deposit whatever the bore: the third run starts from the
    // loading the first two measured (interpolated), not from the scene's 0.3 kg.
    const fs::path dir = scratchDir("calibrate-deposit");
    const auto r = runMixload({"calibrate", "mixer", "--name", "dep", "--dir", dir.string(), "--scene", "gcm250", "--cell-size", "0.01",
                               "--end-time", "0.05", "--allow-unsteady", "--param", "barrel.bore_m=0.09:0.12:0.1",
                               "--target", "39:5:0.2", "--max-evals", "3", "--size-deposit", "--json"});
    const auto j = parsed(r);
    ASSERT_EQ(j["evaluations"].size(), 3u) << r.err;
    const auto run = [&](int i) { return j["evaluations"][i]["runs"][0]; };
    EXPECT_DOUBLE_EQ(run(0)["deposit_kg"].get<double>(), 0.3);
    EXPECT_DOUBLE_EQ(run(1)["deposit_kg"].get<double>(), 0.3);
    const double d2 = run(2)["deposit_kg"].get<double>();
    EXPECT_NE(d2, 0.3);
    const double lo = std::min(run(0)["loading_kg"].get<double>(), run(1)["loading_kg"].get<double>());
    const double hi = std::max(run(0)["loading_kg"].get<double>(), run(1)["loading_kg"].get<double>());
    EXPECT_GE(d2, lo - 0.1 * lo);  // interpolated or extrapolated from the two, not the scene's
    EXPECT_LE(d2, hi + 0.1 * hi);
}

TEST(CalibrateCli, BadInputIsRefusedBeforeAnyRun) {
    const fs::path dir = scratchDir("calibrate-bad");
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
        {{"--param", "weir.nope=1:2", "--target", "39:5:0.3"}, "weir.nope"},
        {{"--param", "weir.chord_angle_deg=20:95", "--target", "39:5:0.3"}, "weir.chord_angle_deg"},
        {{"--param", "weir.chord_angle_deg=60:20", "--target", "39:5:0.3"}, "LO < HI"},
        {{"--param", "weir.chord_angle_deg=20:80", "--target", "39:5:0"}, "target loading"},
        {{"--param", "weir.chord_angle_deg=20:80", "--target", "39:5"}, "RPM:FEED_KG_H:LOADING_KG"},
        {{"--param", "weir.chord_angle_deg=20:80", "--target", "39:5:0.3", "--rpm", "50"}, "target"},
        {{"--param", "operation.initial_loading_kg=0.1:0.4", "--target", "39:5:0.3", "--size-deposit"}, "size-deposit"},
    };
    for (const auto& [extra, needle] : cases) {
        std::vector<std::string> args{"calibrate", "mixer", "--name", "bad", "--dir", dir.string(), "--scene", "gcm250", "--cell-size", "0.01"};
        args.insert(args.end(), extra.begin(), extra.end());
        const auto r = runMixload(args);
        EXPECT_EQ(r.rc, 2) << needle << ": " << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "bad")) << needle;
    }
}
