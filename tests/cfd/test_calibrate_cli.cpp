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
            "--target", "39:5:0.2", "--max-evals", maxEvals, "--json", "--scene", kGcm250At1cm};
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
    const auto r = runMixload({"calibrate", "mixer", "--name", "dep", "--dir", dir.string(), "--scene", kGcm250At1cm, "--cell-size", "0.01",
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
        std::vector<std::string> args{"calibrate", "mixer", "--name", "bad", "--dir", dir.string(), "--scene", kGcm250At1cm, "--cell-size", "0.01"};
        args.insert(args.end(), extra.begin(), extra.end());
        const auto r = runMixload(args);
        EXPECT_EQ(r.rc, 2) << needle << ": " << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "bad")) << needle;
    }
}

// `mixload calibrate collapse` on tiny collapses (Li/8, about 5 s each): data made by a run with a
// known viscosity cap is fitted back to that cap, the second call replays the ledger, and the
// report says whether a squat column keeps its height.
TEST(CalibrateCollapseCli, RecoversAKnownCapAndReplaysItsLedger) {
    const fs::path dir = scratchDir("calibrate-collapse");
    const auto truth = runMixload({"collapse", "--material", "quartz", "--cells-per-length", "8", "--aspect", "1",
                                   "--cap-h-ratio", "10", "--out", (dir / "truth").string(), "--json"});
    ASSERT_EQ(truth.rc, 0) << truth.err;
    const double L = nlohmann::json::parse(truth.out)["runout_star"].get<double>();
    {
        std::ofstream csv(dir / "data.csv");
        csv << "# made by a run with cap_h_ratio = 10\naspect,runout_star,runout_sd,height_star,height_sd\n1,"
            << L << ',' << 0.03 * L << ",,\n";
    }
    const std::vector<std::string> args{"calibrate", "collapse", "--name", "cap", "--dir", dir.string(),
                                        "--material", "quartz", "--cells-per-length", "8",
                                        "--param", "cap_h_ratio=1:100:2:log", "--data", (dir / "data.csv").string(),
                                        "--stop-rms", "0.5", "--json"};
    const auto r = runMixload(args);
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["status"], "within-uncertainty");
    const auto& best = j["best"];
    EXPECT_LE(std::abs(best["runs"][0]["residual_runout"].get<double>()), 0.5);
    // The runout pins the cap: the fitted ratio lies near the one that made the data.
    const double ratio = best["keys"]["cap_h_ratio"].get<double>();
    EXPECT_GT(ratio, 7.0);
    EXPECT_LT(ratio, 14.0);
    EXPECT_GE(j["evaluations"].size(), 2u);
    // The check run at a = 0.5, and the comparison with the paper's fits, are in the report.
    ASSERT_TRUE(j.contains("check"));
    EXPECT_DOUBLE_EQ(j["check"]["aspect"].get<double>(), 0.5);
    EXPECT_EQ(j["check"]["keeps_height"].get<bool>(), j["check"]["height_star"].get<double>() >= 1.0 - 1.0 / 4.0);
    EXPECT_EQ(j["paper_fits"].size(), 4u);
    for (const char* f : {"calibration.md", "calibration.csv", "calibration.json", "calibration.png"})
        EXPECT_TRUE(fs::exists(dir / "cap" / "report" / f)) << f;
    // Again: every run from the ledger, the same answer.
    const auto again = nlohmann::json::parse(runMixload(args).out);
    EXPECT_EQ(again["runs_new"], 0);
    EXPECT_EQ(again["runs_reused"].get<int>(), j["runs_new"].get<int>());
    EXPECT_EQ(again["best"]["keys"], best["keys"]);
}

TEST(CalibrateCollapseCli, BadInputIsRefusedBeforeAnyRun) {
    const fs::path dir = scratchDir("calibrate-collapse-bad");
    {
        std::ofstream csv(dir / "data.csv");
        csv << "aspect,runout_star,runout_sd,height_star,height_sd\n1,1.2,0.1,,\n";
        std::ofstream bad(dir / "bad.csv");
        bad << "aspect,runout_star,runout_sd,height_star,height_sd\n1,1.2,,,\n";
    }
    const std::string data = (dir / "data.csv").string();
    const std::vector<std::pair<std::vector<std::string>, std::string>> cases{
        {{"--param", "mu_x=0.3:0.6", "--data", data}, "mu_x"},
        {{"--param", "cap_h_ratio=1:10", "--param", "eta_max=10:100", "--data", data}, "one of the two caps"},
        {{"--param", "mu_s=0.3:0.6", "--data", data, "--aspect", "2"}, "aspect"},
        {{"--param", "mu_d=0.5:0.9", "--param", "delta_mu=0.1:0.4", "--data", data}, "one of the two"},
        {{"--param", "mu_s=0.3:0.6"}, "--data FILE or --law NAME"},
        {{"--param", "mu_s=0.3:0.6", "--data", (dir / "bad.csv").string()}, "runout_sd"},
        {{"--param", "mu_s=0.3:0.6", "--law", "lube2005", "--aspects", "1,2.3"}, "regimes"},
        {{"--param", "mu_s=0.3:0.6", "--data", (dir / "none.csv").string()}, "none.csv"},
        {{"--param", "mu_s=0.3:0.6:log:x", "--data", data}, "mu_s"},
        {{"--param", "i0=0:0.6", "--data", data}, "i0"},  // the scene refuses I0 = 0 at the range's end
    };
    for (const auto& [extra, needle] : cases) {
        std::vector<std::string> args{"calibrate", "collapse", "--name", "bad", "--dir", dir.string(), "--cells-per-length", "8"};
        args.insert(args.end(), extra.begin(), extra.end());
        const auto r = runMixload(args);
        EXPECT_EQ(r.rc, 2) << needle << ": " << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir / "bad")) << needle;
    }
}

// `mixload stress` (faults and surrogates groups, about a minute): every case ends as a checked
// result or a clear error; a silent failure fails the test with its name.
TEST(StressCli, FaultsAndSurrogatesEndWithoutASilentFailure) {
    const fs::path dir = scratchDir("stress");
    const auto r = runMixload({"stress", "--only", "faults,surrogates", "--out", dir.string(), "--json"});
    EXPECT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_GE(j["cases"].get<int>(), 10);
    EXPECT_EQ(j["silent_failures"], 0) << r.err;
    EXPECT_GE(j["clear_errors"].get<int>(), 6);
    EXPECT_TRUE(fs::exists(dir / "stress.md"));
}

// The silent failures `mixload stress` found, each kept fixed by a test of its own.
TEST(StressCli, ACollapseThatLosesPowderIsRefusedNotReported) {
    // mu_s 0.1: the powder outruns the domain sized for it and leaves through the open side.
    const fs::path dir = scratchDir("stress-lost-powder");
    const auto r = runMixload({"collapse", "--material", "quartz", "--cells-per-length", "8", "--aspect", "1", "--mu-s",
                               "0.1", "--mu-d", "0.4", "--out", (dir / "run").string(), "--json"});
    EXPECT_EQ(r.rc, 1) << r.err;
    EXPECT_NE(r.err.find("powder volume changed"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("open right side"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "run" / "result.json"));
}

TEST(StressCli, AMeshWithoutAnInletFaceIsRefusedBeforeTheSolver) {
    // A feed port narrower than a cell has no face; the solver used to die of a floating-point exception.
    const fs::path dir = scratchDir("stress-no-inlet");
    const auto r = runMixload({"mixer", "--scene", kPinholeInlet1cm, "--cell-size", "0.01", "--end-time", "0.1", "--out",
                               (dir / "run").string(), "--json"});
    EXPECT_EQ(r.rc, 1) << r.err;
    EXPECT_NE(r.err.find("no face on the inlet patch"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "run"));
    // A campaign whose runs fail that way says so on stderr, with --json too.
    ASSERT_EQ(runMixload({"campaign", "create", "c", "--ranges", MIXLOAD_SOURCE_DIR "/data/campaigns/mixer-v2-ranges.toml", "--n",
                          "2", "--scene", kPinholeInlet1cm, "--cell-size", "0.01", "--end-time", "0.1", "--dir", dir.string()})
                  .rc,
              0);
    const auto c = runMixload({"campaign", "run", "c", "--dir", dir.string(), "--json"});
    EXPECT_EQ(c.rc, 1);
    EXPECT_NE(c.err.find("runs failed"), std::string::npos) << c.err;
}
