// SPDX-License-Identifier: GPL-3.0-or-later
// bench pareto-mixer on campaigns whose results are written by hand: the pairing of a hold-out with
// its coarse twin, the errors, the costs and the front; not the solver (tiny runs never reach a
// steady verdict).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <unistd.h>

#include "bench/mixer_pareto.hpp"
#include "campaign/campaign.hpp"
#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "store/ledger.hpp"

namespace fs = std::filesystem;
namespace ex = mixload::experiments;

namespace {
// A smooth loading law of feed and speed (a power law, which the surrogate's log transform makes
// linear): M = 0.1 kg (feed / 10 kg/h)^0.8 (100 rpm / rpm)^0.9.
double law(const nlohmann::json& p) {
    return 0.1 * std::pow(p.value("feed_kg_h", 10.0) / 10, 0.8) * std::pow(100 / p["rpm"].get<double>(), 0.9);
}

// A barrel whose paddles both meshes cut (the default scene's refuse 2 cm): twins of one impeller.
const std::string kScene = MIXLOAD_TEST_DATA "/scenes/v3-2cm.toml";

void create(const fs::path& dir, const std::string& name, const std::string& design, int n, std::optional<double> cell) {
    ex::CampaignSpec spec;
    spec.place = {name, dir.string()};
    spec.ranges = (dir / "r.toml").string();
    spec.design = design;
    spec.n = n;
    spec.scene = kScene;
    spec.cellSize = cell;
    ex::createCampaign(spec);
}

// Every point done and steady with scale x the law, at coreSeconds each; point `unsteady` without a verdict.
void finish(const fs::path& dir, const std::string& name, double scale, double coreSeconds, int unsteady = -1) {
    mixload::store::Ledger l(dir / name / "ledger.sqlite");
    while (auto r = l.claimNext(name, 2, false))
        l.markDone(r->id, {{"loading_kg", scale * law(r->params)}, {"steady", r->index != unsteady}}, coreSeconds, coreSeconds, "/x");
}
}  // namespace

TEST(MixerPareto, PairsTheHoldOutWithItsCoarseTwinAndRanksTheMethods) {
    const fs::path dir = fs::temp_directory_path() / ("mixload-mixer-pareto-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    mixload::writeFileAtomic(dir / "r.toml", "scene = \"mixer\"\n[rpm]\nmin = 39\nmax = 254\nunit = \"rpm\"\n"
                                             "[feed_kg_h]\nmin = 5\nmax = 45\nunit = \"kg/h\"\nscale = \"log\"\n");
    create(dir, "train", "sobol", 16, std::nullopt);
    create(dir, "hold", "lhs", 6, std::nullopt);
    create(dir, "hold2cm", "lhs", 6, 0.02);  // the same design on 2 cm
    create(dir, "other", "lhs", 6, 0.02);
    finish(dir, "train", 1.0, 50);
    finish(dir, "hold", 1.0, 100, 2);       // one hold-out run without a verdict: five answer
    finish(dir, "hold2cm", 0.8, 10);        // the coarse mesh 20% light everywhere
    {
        // A campaign of another design is refused as a coarse twin.
        mixload::writeFileAtomic(dir / "r2.toml", "scene = \"mixer\"\n[rpm]\nmin = 40\nmax = 250\nunit = \"rpm\"\n");
        ex::CampaignSpec spec;
        spec.place = {"otherdesign", dir.string()};
        spec.ranges = (dir / "r2.toml").string();
        spec.n = 6;
        spec.scene = kScene;
        ex::createCampaign(spec);
        finish(dir, "otherdesign", 1.0, 10);
    }
    ex::MixerPareto b{{"train", dir.string()}, {"hold", dir.string()}, {{"hold2cm", dir.string()}}, dir / "out"};
    const auto j = ex::runMixerPareto(b);
    EXPECT_EQ(j["holdout_steady_runs"], 5);
    EXPECT_EQ(j["train_steady_runs"], 16);
    EXPECT_DOUBLE_EQ(j["train_core_seconds"].get<double>(), 16 * 50.0);
    std::map<std::string, nlohmann::json> by;
    for (const auto& m : j["pareto"]) by[m["method"].get<std::string>()] = m;
    ASSERT_TRUE(by.count("full run, 1 cm (reference, 5)")) << j["pareto"].dump(1);
    ASSERT_TRUE(by.count("full run, 2 cm, hold2cm (5)")) << j["pareto"].dump(1);
    const auto& coarse = by["full run, 2 cm, hold2cm (5)"];
    EXPECT_NEAR(coarse["median_error"].get<double>(), 0.2, 1e-12);
    EXPECT_NEAR(coarse["max_error"].get<double>(), 0.2, 1e-12);
    EXPECT_DOUBLE_EQ(coarse["seconds"].get<double>(), 10.0);
    EXPECT_DOUBLE_EQ(by["full run, 1 cm (reference, 5)"]["seconds"].get<double>(), 100.0);
    // A power law in the surrogates' log variables: the response surface (a quadratic in them)
    // is exact and answers in far less than a millisecond, so it beats the coarse runs and kriging
    // on both counts; kriging on 16 runs is within 0.1%. The reference stays on the front (no
    // error), and the models' offline cost is the training campaign's.
    const auto& rsm = by["response surface (5)"];
    EXPECT_LT(rsm["max_error"].get<double>(), 1e-9) << rsm;
    EXPECT_LT(rsm["seconds"].get<double>(), 1e-3);
    EXPECT_TRUE(rsm["front"].get<bool>());
    const auto& k = by["kriging (loading surrogate) (5)"];
    EXPECT_LT(k["max_error"].get<double>(), 1e-3) << k;
    EXPECT_FALSE(k["front"].get<bool>());
    EXPECT_FALSE(coarse["front"].get<bool>());
    EXPECT_TRUE(by["full run, 1 cm (reference, 5)"]["front"].get<bool>());
    EXPECT_GE(k["offline_seconds"].get<double>(), 16 * 50.0);
    // Paired with kriging (within 0.1% here), the coarse twin is 20 points worse on every run, so
    // its bootstrap interval is 20 points wide at most 0.1.
    std::map<std::string, nlohmann::json> paired;
    for (const auto& p : j["paired_with_kriging"]) paired[p["method"].get<std::string>()] = p;
    ASSERT_TRUE(paired.count("full run, 2 cm, hold2cm")) << j["paired_with_kriging"].dump(1);
    const auto& pc = paired["full run, 2 cm, hold2cm"];
    EXPECT_EQ(pc["runs"], 5);
    EXPECT_NEAR(pc["mean_abs_error_minus_kriging"].get<double>(), 0.2, 1e-3);
    EXPECT_NEAR(pc["ci90"][0].get<double>(), 0.2, 1e-3);
    EXPECT_NEAR(pc["ci90"][1].get<double>(), 0.2, 1e-3);
    // Without snapshots the POD regression (both fields, read once) says why it is missing.
    ASSERT_EQ(j["notes"].size(), 1u);
    EXPECT_NE(j["notes"][0].get<std::string>().find("snapshots"), std::string::npos) << j["notes"][0];
    EXPECT_TRUE(fs::exists(dir / "out" / "pareto.md"));
    EXPECT_TRUE(fs::exists(dir / "out" / "runs.csv"));
    EXPECT_EQ(j["runs"].size(), 5u);
    // A coarse campaign of another design, and too few training runs, are refused.
    b.coarse = {{"otherdesign", dir.string()}};
    EXPECT_THROW(ex::runMixerPareto(b), mixload::InputError);
    b.coarse.clear();
    b.train = {"hold", dir.string()};
    EXPECT_NO_THROW(ex::runMixerPareto(b));  // five steady runs: enough
    b.train = {"other", dir.string()};       // none finished
    EXPECT_THROW(ex::runMixerPareto(b), mixload::InputError);
    fs::remove_all(dir);
}
