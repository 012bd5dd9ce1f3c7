// SPDX-License-Identifier: GPL-3.0-or-later
// The surrogate commands as users run them: fit from a table, predict (warnings outside the
// training box, exit 2 on non-physical input), batch prediction, what-if, check with a threshold;
// and the shipped model against the shipped campaign, with the figures the README quotes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "common/atomic_file.hpp"

using namespace mixload::testing;
namespace fs = std::filesystem;

namespace {

// A synthetic campaign export: a smooth loading law on 40 points, as `campaign export` writes it.
fs::path syntheticTable(const fs::path& dir, unsigned seed = 3) {
    std::mt19937 g(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::ostringstream os;
    os << "# synthetic\nindex,mu_s,delta_mu,i0,d,rho,feed_kg_h,rpm,scene_hash,status,loading_kg,steady\n";
    for (int i = 0; i < 40; ++i) {
        const double mus = 0.2 + 0.25 * u(g), dmu = 0.05 + 0.25 * u(g), i0 = 0.1 + 0.5 * u(g), d = 1e-4 + 3e-4 * u(g),
                     rho = 250 + 350 * u(g), feed = 5 + 40 * u(g), rpm = 39 + 215 * u(g);
        const double m = 0.03 * std::pow(feed / 20, 0.65) * std::pow(rpm / 100, -0.4) * (1 + 0.3 * (mus - 0.3));
        os << std::setprecision(17) << i << ',' << mus << ',' << dmu << ',' << i0 << ',' << d << ',' << rho << ',' << feed
           << ',' << rpm << ",h" << i << ",done," << m << ",true\n";
    }
    os << "40,0.3,0.1,0.3,2e-4,300,10,100,h40,failed,,\n";  // not usable: skipped
    const fs::path f = dir / "runs.csv";
    mixload::writeFileAtomic(f, os.str());
    return f;
}

const std::vector<std::string> kAvicel{"--mu-s", "0.31", "--mu-d", "0.44", "--i0", "0.28", "--d", "240e-6", "--rho", "329.84"};

std::vector<std::string> cat(std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

}  // namespace

TEST(SurrogateCli, FitPredictWhatifCheck) {
    const fs::path dir = scratchDir("surrogate-cli");
    const fs::path table = syntheticTable(dir), model = dir / "k.json";
    auto r = runMixload({"surrogate", "fit", "--table", table.string(), "--kind", "kriging", "--holdout", "8", "-o",
                         model.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["n_train"], 32);
    EXPECT_EQ(j["n_holdout"], 8);
    // A trend input the model does not have: exit 2 naming it and the allowed inputs, no file.
    r = runMixload({"surrogate", "fit", "--table", table.string(), "--trend-inputs", "feed/rho", "-o", (dir / "t.json").string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("trend-inputs = feed/rho: allowed one of this model's inputs: mu_s,"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "t.json"));

    r = runMixload(cat({"predict", "--model", model.string(), "--feed-kg-h", "20", "--rpm", "100", "--json"}, kAvicel));
    ASSERT_EQ(r.rc, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    const double expected = 0.03 * std::pow(20.0 / 20, 0.65) * std::pow(100.0 / 100, -0.4) * (1 + 0.3 * 0.01);
    EXPECT_NEAR(j["loading_kg"].get<double>(), expected, 0.05 * expected);
    EXPECT_TRUE(j["in_training_box"].get<bool>());
    EXPECT_LE(j["ci95_kg"][0].get<double>(), j["loading_kg"].get<double>());
    EXPECT_GE(j["ci95_kg"][1].get<double>(), j["loading_kg"].get<double>());
    EXPECT_TRUE(r.err.empty()) << r.err;

    // Just outside the box: a warning on stderr and in the JSON, not silence.
    r = runMixload(cat({"predict", "--model", model.string(), "--feed-kg-h", "50", "--rpm", "100", "--json"}, kAvicel));
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_FALSE(nlohmann::json::parse(r.out)["in_training_box"].get<bool>());
    EXPECT_NE(r.err.find("outside the training box: feed_kg_h = 50"), std::string::npos) << r.err;
    // Far outside: refused with the input named, unless the user asks to extrapolate; then the
    // interval stays physical.
    r = runMixload(cat({"predict", "--model", model.string(), "--feed-kg-h", "500", "--rpm", "100"}, kAvicel));
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("feed_kg_h = 500"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("--extrapolate"), std::string::npos) << r.err;
    r = runMixload(cat({"predict", "--model", model.string(), "--feed-kg-h", "500", "--rpm", "100", "--extrapolate", "--json"}, kAvicel));
    ASSERT_EQ(r.rc, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_GE(j["ci95_kg"][0].get<double>(), 0.0);
    EXPECT_GT(j["outside_distance"].get<double>(), 1.0);  // in the model's units: log feed here

    // Non-physical input: exit 2, one clear line.
    for (const auto& [flag, value, needle] : std::vector<std::array<std::string, 3>>{
             {"--mu-d", "0.2", "mu-d"}, {"--d", "-1e-4", "d"}, {"--rpm", "0", "rpm"}}) {
        auto args = cat({"predict", "--model", model.string(), "--feed-kg-h", "20", "--rpm", "100"}, kAvicel);
        for (size_t i = 0; i + 1 < args.size(); ++i)
            if (args[i] == flag) args[i + 1] = value;
        r = runMixload(args);
        EXPECT_EQ(r.rc, 2) << flag;
        EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }

    // A missing input: exit 2, naming the flag, its unit and the paper's value as an example.
    r = runMixload({"predict", "--model", model.string(), "--feed-kg-h", "20", "--rpm", "100"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("invalid --mu-s = (missing): allowed a number (dimensionless), e.g. 0.31"), std::string::npos)
        << r.err;
    r = runMixload(cat({"predict", "--model", model.string(), "--feed-kg-h", "20"}, kAvicel));
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("--rpm = (missing): allowed a number [rpm], e.g. 39"), std::string::npos) << r.err;

    // Batch: one output row per input row.
    const fs::path out = dir / "pred.csv";
    r = runMixload({"predict", "--model", model.string(), "--batch", table.string(), "-o", out.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    const std::string csv = mixload::readFile(out);
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 42);  // header + 41 rows (the failed row has inputs)

    r = runMixload(cat({"whatif", "--model", model.string(), "--change", "rho=+50%", "--change", "mu_s=-10%", "--at", "20:100",
                        "--at", "30:150", "--json"},
                       kAvicel));
    ASSERT_EQ(r.rc, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["points"].size(), 2u);
    const auto& p = j["points"][0];
    EXPECT_NEAR(j["new"]["rho"].get<double>(), 329.84 * 1.5, 1e-9);
    EXPECT_NEAR(j["new"]["mu_s"].get<double>(), 0.279, 1e-12);
    EXPECT_NEAR(p["delta_kg"].get<double>(), p["new"]["loading_kg"].get<double>() - p["base"]["loading_kg"].get<double>(), 1e-15);
    double sum = p["interaction_kg"];
    for (const auto& a : p["attribution"]) sum += a["delta_kg"].get<double>();
    EXPECT_NEAR(sum, p["delta_kg"].get<double>(), 1e-12);
    EXPECT_EQ(p["attribution"].size(), 2u);
    // The interval of the difference uses the two predictions' correlation: no wider than if
    // they were independent.
    EXPECT_LE(p["delta_ci95_kg"][0].get<double>(), p["delta_kg"].get<double>());
    EXPECT_GE(p["delta_ci95_kg"][1].get<double>(), p["delta_kg"].get<double>());
    EXPECT_GT(p["error_correlation"].get<double>(), 0.0);
    EXPECT_LT(p["delta_ci95_kg"][1].get<double>() - p["delta_ci95_kg"][0].get<double>(),
              p["delta_ci95_independent_kg"][1].get<double>() - p["delta_ci95_independent_kg"][0].get<double>());

    // Check: 8 hold-out runs, 32 by LOO; a threshold below the error fails with exit 1.
    r = runMixload({"check", "--model", model.string(), "--table", table.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["n_holdout"], 8);
    EXPECT_EQ(j["loo"]["n"], 32);
    for (const char* k : {"mean_rel_error", "max_rel_error", "coverage95"}) EXPECT_TRUE(j[k].is_number()) << k;
    ASSERT_TRUE(j.contains("label_noise"));
    EXPECT_TRUE(j["label_noise"].is_null());  // a table has no replicates to measure it by
    // Every run is listed with its inputs; the per-run errors average to the printed means.
    ASSERT_EQ(j["holdout"].size(), 8u);
    ASSERT_EQ(j["loo"]["runs"].size(), 32u);
    for (const auto* set : {&j["holdout"], &j["loo"]["runs"]}) {
        double sum = 0;
        for (const auto& e : *set) {
            EXPECT_EQ(e["inputs"].size(), 7u) << e.dump();
            EXPECT_NEAR(e["rel_error"].get<double>(),
                        std::abs(e["predicted_kg"].get<double>() - e["loading_kg"].get<double>()) / e["loading_kg"].get<double>(), 1e-12);
            sum += e["rel_error"].get<double>();
        }
        EXPECT_NEAR(sum / static_cast<double>(set->size()),
                    (set == &j["holdout"] ? j : j["loo"])["mean_rel_error"].get<double>(), 1e-12);
    }
    // --runs prints them all, worst first.
    r = runMixload({"check", "--model", model.string(), "--table", table.string(), "--no-record", "--runs"});
    ASSERT_EQ(r.rc, 0) << r.err;
    for (const auto& e : j["holdout"]) EXPECT_NE(r.out.find(e["id"].get<std::string>()), std::string::npos) << e["id"];
    std::string worstId;
    double worstError = -1;
    for (const auto* set : {&j["holdout"], &j["loo"]["runs"]})
        for (const auto& e : *set)
            if (e["rel_error"].get<double>() > worstError) worstError = e["rel_error"], worstId = e["id"];
    const auto listed = r.out.substr(r.out.find("worst first"));
    const auto firstRow = listed.find('\n', listed.find('\n') + 1) + 1;  // after the title and the header
    EXPECT_EQ(listed.substr(firstRow, worstId.size() + 2), "  " + worstId) << listed;
    // --plot draws every checked run: one data row per run, the runs outside their interval apart.
    r = runMixload({"check", "--model", model.string(), "--table", table.string(), "--no-record", "--plot", (dir / "parity").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["plot"], (dir / "parity" / "parity.png").string());
    EXPECT_TRUE(fs::exists(dir / "parity" / "parity.png"));
    {
        std::istringstream dat(mixload::readFile(dir / "parity" / "parity.dat"));
        int rows = 0, outsideRows = -1;
        for (std::string line; std::getline(dat, line);) {
            if (line.rfind("# hold-out, outside", 0) == 0) outsideRows = 0;
            else if (!line.empty() && line[0] != '#') ++rows, outsideRows += outsideRows >= 0;
        }
        EXPECT_EQ(rows, 8 + 32);
        int outside = 0;
        for (const auto& e : j["holdout"]) {
            const bool miss = e["loading_kg"] < e["ci95_kg"][0] || e["loading_kg"] > e["ci95_kg"][1];
            EXPECT_EQ(e["in_ci95"], !miss) << e.dump();
            outside += miss;
        }
        EXPECT_EQ(std::max(outsideRows, 0), outside);
    }
    r = runMixload({"check", "--model", model.string(), "--table", table.string(), "--threshold", "1e-9"});
    EXPECT_EQ(r.rc, 1);
    EXPECT_NE(r.err.find("exceeds --threshold"), std::string::npos) << r.err;
    const auto history = nlohmann::json::parse(mixload::readFile(model))["checks"];
    // The same runs checked twice (and once with --no-record) are recorded once, without the per-run lists.
    EXPECT_EQ(history.size(), 1u);
    EXPECT_NE(r.out.find("already in the model's check history"), std::string::npos) << r.out;
    for (const auto& c : history) EXPECT_FALSE(c["loo"].contains("runs")) << c.dump();
}

TEST(SurrogateCli, CurveHoldsOutTheLastRunsOrAnotherSetOfRuns) {
    // Issue 16's hold-out is a design of its own (a second campaign), not the tail of the training
    // design: the learning curve takes either.
    const fs::path dir = scratchDir("surrogate-curve");
    const fs::path table = syntheticTable(dir);
    auto r = runMixload({"surrogate", "curve", "--table", table.string(), "--holdout", "10", "--sizes", "10,30", "--out",
                         (dir / "tail").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["n_holdout"], 10);
    ASSERT_EQ(j["points"].size(), 2u);
    // The same 40 runs as the training set, checked on a second table of the same law.
    fs::create_directories(dir / "other");
    const fs::path other = syntheticTable(dir / "other", 4);
    r = runMixload({"surrogate", "curve", "--table", table.string(), "--holdout-table", other.string(), "--sizes", "10,40",
                    "--out", (dir / "table").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["n_holdout"], 40);
    EXPECT_EQ(j["holdout_source"]["table"], other.string());
    EXPECT_EQ(j["points"][1]["n"], 40);
    EXPECT_LT(j["points"][1]["holdout_mean"].get<double>(), j["points"][0]["holdout_mean"].get<double>());
    EXPECT_TRUE(fs::exists(dir / "table" / "curve.png"));
    // Exactly one hold-out; the training runs themselves are not one.
    for (const auto& extra : std::vector<std::vector<std::string>>{{}, {"--holdout", "5", "--holdout-table", other.string()},
                                                                   {"--holdout-table", table.string()}}) {
        auto args = std::vector<std::string>{"surrogate", "curve", "--table", table.string(), "--out", (dir / "bad").string()};
        args.insert(args.end(), extra.begin(), extra.end());
        r = runMixload(args);
        EXPECT_EQ(r.rc, 2) << r.out;
        EXPECT_NE(r.err.find("holdout"), std::string::npos) << r.err;
    }
}

TEST(SurrogateCli, BadModelFilesAreRefused) {
    const fs::path dir = scratchDir("surrogate-bad");
    const fs::path bad = dir / "bad.json";
    mixload::writeFileAtomic(bad, R"({"schema": "mixload-surrogate", "schema_version": 99})");
    auto r = runMixload(cat({"predict", "--model", bad.string(), "--feed-kg-h", "20", "--rpm", "100"}, kAvicel));
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("schema version 99"), std::string::npos) << r.err;
    r = runMixload(cat({"predict", "--model", (dir / "none.json").string(), "--feed-kg-h", "20", "--rpm", "100"}, kAvicel));
    EXPECT_EQ(r.rc, 2);
    r = runMixload({"surrogate", "fit", "--table", (dir / "none.csv").string(), "-o", (dir / "m.json").string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_FALSE(fs::exists(dir / "m.json"));
}

TEST(SurrogateCli, AModelNamesTheMeshItsCampaignRanOn) {
    // Campaign v2's base names its mesh by level ("coarse"), which on gcm250-v2 is the 1 cm O-grid:
    // a model fitted from it says both, so that nobody reads "coarse" as the coarsest mesh.
    const fs::path dir = scratchDir("surrogate-mesh-label");
    auto r = runMixload({"surrogate", "fit", "--table", std::string(MIXLOAD_DATA_DIR) + "/campaigns/mixer-v2.csv", "--kind", "rsm",
                         "--similarity", "-o", (dir / "r.json").string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = runMixload({"surrogate", "info", (dir / "r.json").string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(r.out.find("scene gcm250-v2, mrf, coarse mesh, 0.01 m (ogrid)"), std::string::npos) << r.out;
}

TEST(SurrogateCli, ShippedModelsReproduceTheirRecordedAccuracy) {
    // The shipped models belong to the calibrated scene (gcm250-v2, 1 cm O-grid) and train on the
    // export of its campaign v2 under data/. `mixload check` without --campaign or --table finds
    // that table from any directory and reproduces the leave-one-out figures the fit recorded (the
    // README's table); the superseded scene's models stay apart.
    for (const char* name : {"mixer-loading-kriging.json", "mixer-loading-rsm.json"}) {
        const std::string path = std::string(MIXLOAD_DATA_DIR) + "/models/" + name;
        const auto model = nlohmann::json::parse(mixload::readFile(path));
        EXPECT_EQ(model["provenance"]["source"]["base"]["scene"], "gcm250-v2") << name;
        EXPECT_EQ(model["provenance"]["source"]["campaign"], "v2") << name;
        const auto r = runMixload({"check", "--model", path, "--no-record", "--json"});
        ASSERT_EQ(r.rc, 0) << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["loo"]["n"], model["training_ids"].size()) << name;
        EXPECT_GE(model["training_ids"].size(), 10u) << name;
        for (const char* k : {"mean_rel_error", "max_rel_error", "coverage95"})
            EXPECT_NEAR(j["loo"][k].get<double>(), model["validation"][k].get<double>(), 1e-9) << name << ' ' << k;
    }
    // Runs of another scene (campaign v2c-holdout: the same scene on 2 cm) are checked but never
    // recorded in the model's history; the model's own campaign is.
    const fs::path dir = scratchDir("shipped-check");
    const fs::path copy = dir / "k.json";
    fs::copy_file(std::string(MIXLOAD_DATA_DIR) + "/models/mixer-loading-kriging.json", copy);
    const auto history = [&] { return nlohmann::json::parse(mixload::readFile(copy))["checks"].size(); };
    const auto before = history();
    auto r = runMixload({"check", "--model", copy.string(), "--table", std::string(MIXLOAD_DATA_DIR) + "/campaigns/mixer-v2c-holdout.csv", "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["same_scene"], false);
    EXPECT_NE(r.err.find("another scene"), std::string::npos) << r.err;
    EXPECT_EQ(history(), before);
    r = runMixload({"check", "--model", copy.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["same_scene"], true);
    EXPECT_EQ(history(), before + 1);

    // The superseded scene's figures quoted in docs/surrogates.md (24 hold-out runs, 32 by LOO).
    struct Expected {
        const char* model;
        double holdMean, holdCov, looMean;
    };
    for (const auto& e : {Expected{"gcm250-avicel-kriging.json", 0.13499489567644593, 0.7083333333333334, 0.08384634816529583},
                          Expected{"gcm250-avicel-rsm.json", 0.22723819577144766, 0.5, 0.06746800053751628}}) {
        const std::string path = std::string(MIXLOAD_DATA_DIR) + "/models/superseded/" + e.model;
        EXPECT_EQ(nlohmann::json::parse(mixload::readFile(path))["provenance"]["source"]["base"]["scene"], "gcm250") << e.model;
        const auto r = runMixload({"check", "--model", path, "--campaign", "mixer-avicel", "--dir",
                                   std::string(MIXLOAD_DATA_DIR) + "/campaigns", "--no-record", "--json"});
        ASSERT_EQ(r.rc, 0) << r.err;
        const auto j = nlohmann::json::parse(r.out);
        EXPECT_EQ(j["n_holdout"], 24) << e.model;
        EXPECT_NEAR(j["mean_rel_error"].get<double>(), e.holdMean, 1e-9) << e.model;
        EXPECT_NEAR(j["coverage95"].get<double>(), e.holdCov, 1e-12) << e.model;
        EXPECT_NEAR(j["loo"]["mean_rel_error"].get<double>(), e.looMean, 1e-9) << e.model;
    }
}

// Sobol indices of the shipped model over its campaign's box: the indices are shares of the
// variance, the table and plot are written, and a box that is not a mixer's is refused.
TEST(SurrogateCli, SensitivityWritesSobolIndices) {
    const fs::path dir = scratchDir("sensitivity");
    auto r = runMixload({"sensitivity", "--n", "512", "--bootstrap", "50", "--out", (dir / "s").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["indices"].size(), 7u);
    EXPECT_EQ(j["evaluations"], 512 * 9);
    double firstSum = 0, totalSum = 0;
    for (const auto& ix : j["indices"]) {
        firstSum += ix["first"].get<double>();
        totalSum += ix["total"].get<double>();
        EXPECT_GE(ix["total"].get<double>(), -0.01) << ix.dump();
        EXPECT_LE(ix["total_ci90"][0].get<double>(), ix["total"].get<double>() + 1e-12) << ix.dump();
        EXPECT_GE(ix["total_ci90"][1].get<double>(), ix["total"].get<double>() - 1e-12) << ix.dump();
    }
    // Shares of one variance, whatever the model: first-order ones add up to at most 1, total ones
    // (each counting its interactions) to at least 1, up to the estimators' noise at n = 512.
    EXPECT_LT(firstSum, 1.1);
    EXPECT_GT(totalSum, 0.9);
    EXPECT_LE(firstSum, totalSum + 0.05);
    EXPECT_TRUE(fs::exists(dir / "s" / "sensitivity.md"));
    EXPECT_TRUE(fs::exists(dir / "s" / "sensitivity.csv"));
    const fs::path collapse = dir / "collapse.toml";
    mixload::writeFileAtomic(collapse, "scene = \"collapse\"\n[aspect]\nmin = 1\nmax = 3\nunit = \"1\"\n");
    r = runMixload({"sensitivity", "--ranges", collapse.string(), "--out", (dir / "c").string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("mixer"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "c"));
}

// The what-if a process engineer hands on: the paper's change over a 2 x 3 operating map, as a
// table, a CSV with one row per point, and a plot; a bad map is refused before anything is written.
TEST(SurrogateCli, WhatifReportCoversTheOperatingMap) {
    const fs::path dir = scratchDir("whatif-report");
    const std::vector<std::string> avicel{"--mu-s", "0.31", "--mu-d", "0.44", "--i0", "0.28", "--d", "240e-6", "--rho", "329.84"};
    std::vector<std::string> args{"whatif", "--change", "rho=+50%", "--change", "mu_s=-10%", "--feeds", "10,30", "--rpms", "60,120,200",
                                  "--report", (dir / "r").string(), "--json"};
    args.insert(args.begin() + 1, avicel.begin(), avicel.end());
    auto r = runMixload(args);
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["points"].size(), 6u);
    for (const auto& p : j["points"])
        EXPECT_NEAR(p["delta_kg"].get<double>(), p["new"]["loading_kg"].get<double>() - p["base"]["loading_kg"].get<double>(), 1e-15);
    std::ifstream csv(dir / "r" / "report.csv");
    std::string line;
    int rows = -1;
    while (std::getline(csv, line)) ++rows;
    EXPECT_EQ(rows, 6);
    EXPECT_TRUE(fs::exists(dir / "r" / "report.md"));
    // A loading above a full barrel of the powder is marked in the table and the CSV, and said:
    // the shipped model given a barrel of 10 cm3 (3 g of the base powder).
    auto small = nlohmann::json::parse(mixload::readFile(std::string(MIXLOAD_DATA_DIR) + "/models/mixer-loading-kriging.json"));
    small["provenance"]["full_barrel_m3"] = 1e-5;
    mixload::writeFileAtomic(dir / "small.json", small.dump());
    auto tiny = args;
    tiny.pop_back();  // --json
    tiny[tiny.size() - 1] = (dir / "tiny").string();
    tiny.insert(tiny.end(), {"--model", (dir / "small.json").string()});
    r = runMixload(tiny);
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(r.err.find("exceeds a full barrel"), std::string::npos) << r.err;
    const std::string tinyCsv = mixload::readFile(dir / "tiny" / "report.csv");
    EXPECT_NE(tinyCsv.find(",above_full_barrel\n"), std::string::npos) << tinyCsv;
    EXPECT_NE(tinyCsv.find(",true\n"), std::string::npos) << tinyCsv;
    EXPECT_NE(mixload::readFile(dir / "tiny" / "report.md").find("above a full barrel: not valid"), std::string::npos);
    EXPECT_EQ(mixload::readFile(dir / "r" / "report.csv").find(",true\n"), std::string::npos) << "no row of the shipped model is above a full barrel";
    args.back() = "--feeds";
    args.push_back("10,-5");
    args[args.size() - 3] = (dir / "bad").string();
    r = runMixload(args);
    EXPECT_EQ(r.rc, 2) << r.out;
    EXPECT_FALSE(fs::exists(dir / "bad"));
}

// The paper's Fig. 8 from the shipped model: M over (mu_s, rho) at the reference point, the two
// arrows agreeing with `whatif` on the same change, the full runs that lie on the plane (and only
// those) compared, and bad axes or arrows refused (exit 2) before anything is written.
TEST(SurrogateCli, PlaneDrawsThePapersFig8) {
    const fs::path dir = scratchDir("plane");
    const fs::path checks = dir / "runs.csv";
    mixload::writeFileAtomic(checks,
                             "scene_hash,mu_s,mu_d,i0,d,rho,feed_kg_h,rpm,loading_kg,steady\n"
                             "on-a,0.25,0.44,0.28,0.00024,400,5,39,0.03,true\n"
                             "on-a-again,0.25,0.44,0.28,0.00024,400,5,39,0.031,true\n"
                             "on-b,0.35,0.44,0.28,0.00024,300,5,39,0.02,true\n"
                             "off-feed,0.31,0.44,0.28,0.00024,329.84,6,39,0.03,true\n"
                             "unsteady,0.31,0.44,0.28,0.00024,329.84,5,39,0.03,false\n");
    auto r = runMixload({"plane", "--n", "11", "--checks", checks.string(), "--out", (dir / "p").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["x"]["input"], "mu_s");
    EXPECT_EQ(j["y"]["input"], "rho");
    EXPECT_EQ(j["grid_points"], 121);  // mu_s 0.2-0.42 stays below mu_d = 0.44
    ASSERT_EQ(j["arrows"].size(), 2u);
    ASSERT_EQ(j["checks"].size(), 3u);
    for (const auto& c : j["checks"]) EXPECT_EQ(c["id"].get<std::string>().substr(0, 3), "on-") << c.dump();
    for (const char* f : {"plane.md", "plane.csv", "plane.png"}) EXPECT_TRUE(fs::exists(dir / "p" / f)) << f;
    // The two runs at one point are drawn as one square whose label lists both loadings.
    const std::string squares = mixload::readFile(dir / "p" / "plane-checks.dat");
    EXPECT_EQ(std::count(squares.begin(), squares.end(), '\n'), 2) << squares;
    EXPECT_NE(squares.find("\"0.03, 0.031\""), std::string::npos) << squares;

    // The first arrow is the paper's first what-if: the same dM as `whatif` gives.
    r = runMixload({"whatif", "--mu-s", "0.31", "--mu-d", "0.44", "--i0", "0.28", "--d", "240e-6", "--rho", "329.84", "--change",
                    "rho=+50%", "--change", "mu_s=-10%", "--feed-kg-h", "5", "--rpm", "39", "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto w = nlohmann::json::parse(r.out);
    EXPECT_NEAR(j["arrows"][0]["dm_kg"].get<double>(), w["points"][0]["delta_kg"].get<double>(), 1e-12) << w.dump();

    for (const auto& bad : std::vector<std::vector<std::string>>{{"--y", "mu_s"},
                                                                  {"--x-range", "0.4:0.2"},
                                                                  {"--x", "colour"},
                                                                  {"--arrow", "rho=+50"},
                                                                  {"--y-range", "-1:600"}}) {
        std::vector<std::string> args{"plane", "--out", (dir / "bad").string()};
        args.insert(args.end(), bad.begin(), bad.end());
        r = runMixload(args);
        EXPECT_EQ(r.rc, 2) << bad[0] << ' ' << bad[1] << ": " << r.err;
        EXPECT_FALSE(fs::exists(dir / "bad")) << bad[0];
    }
}
