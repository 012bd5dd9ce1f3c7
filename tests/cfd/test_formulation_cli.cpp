// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload study formulation` on tiny real runs: the reference and a variant run, the table and
// the plot are written, a run without a steady verdict gets no pass or fail, and a variant the
// scene refuses stops the study before any run; a study started warm from a run.
#include <gtest/gtest.h>

#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

using namespace mixload::testing;
namespace fs = std::filesystem;

TEST(FormulationStudy, RunsTheReferenceAndEachVariantAndJudgesOnlySteadyRuns) {
    const fs::path out = scratchDir("formulation") / "study";
    const auto r = runMixload({"study", "formulation", "--variant", "denser:rho=1.5,mu_s=0.9", "--scene", "gcm250", "--cell-size", "0.01",
                               "--end-time", "0.05", "--out", out.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["rows"].size(), 1u);
    const auto& row = j["rows"][0];
    EXPECT_EQ(row["verdict"], "open: not steady");
    EXPECT_EQ(j["open"], 1);
    // The variant's run has the changed powder; the deposit is the same mass in both.
    const auto scene = [](const nlohmann::json& res) {
        return nlohmann::json::parse(std::ifstream(fs::path(res["run_dir"].get<std::string>()) / "scene.json"))["scene"];
    };
    const auto s0 = scene(j["reference"]), s1 = scene(row);
    EXPECT_NEAR(s1["material"]["bulk_density_kg_m3"].get<double>() / s0["material"]["bulk_density_kg_m3"].get<double>(), 1.5, 1e-12);
    EXPECT_NEAR(s1["material"]["mu_s"].get<double>() / s0["material"]["mu_s"].get<double>(), 0.9, 1e-12);
    EXPECT_NEAR(row["loading_kg"].get<double>(), j["reference"]["loading_kg"].get<double>(), 0.03);
    for (const char* f : {"table.md", "table.csv", "formulation.png", "study.json"})
        EXPECT_TRUE(fs::exists(out / f)) << f;
    // Run again: both runs come from the run store.
    const auto again = runMixload({"study", "formulation", "--variant", "denser:rho=1.5,mu_s=0.9", "--scene", "gcm250", "--cell-size",
                                   "0.01", "--end-time", "0.05", "--out", out.string(), "--json"});
    ASSERT_EQ(again.rc, 0) << again.err;
    EXPECT_EQ(nlohmann::json::parse(again.out)["rows"][0]["loading_kg"], row["loading_kg"]);
}

TEST(FormulationStudy, AVariantTheSceneRefusesStopsItBeforeAnyRun) {
    const fs::path out = scratchDir("formulation-bad") / "study";
    for (const auto& [variant, needle] : std::vector<std::pair<std::string, std::string>>{
             {"weak:mu_d=0.5", "mu_d"}, {"x:rho=-1", "factor > 0"}, {"x:colour=2", "mu_s | mu_d"}, {"nocolon", "NAME:"}}) {
        const auto r = runMixload({"study", "formulation", "--variant", variant, "--out", out.string()});
        EXPECT_EQ(r.rc, 2) << variant << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out)) << variant;
    }
}

TEST(FormulationStudy, WarmFromARunStartsEveryRunFromItsFieldsInRunsOfTheirOwn) {
    // Every run of the study begins from the source's last fields: the reference with the
    // source's loading, the denser variant with 1.5 times it (the same powder volume). Warm runs
    // live beside cold ones under their own names; a bad source stops the study before any run.
    const fs::path dir = scratchDir("formulation-warm");
    const auto src = runMixload({"mixer", "--scene", "gcm250", "--cell-size", "0.01", "--end-time", "0.05", "--out",
                                 (dir / "source").string(), "--json"});
    ASSERT_EQ(src.rc, 0) << src.err;
    const double m0 = nlohmann::json::parse(src.out)["final_loading_kg"].get<double>();
    const auto r = runMixload({"study", "formulation", "--variant", "denser:rho=1.5", "--scene", "gcm250",
                               "--cell-size", "0.01", "--end-time", "0.03", "--warm-from", (dir / "source").string(),
                               "--out", (dir / "study").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["warm_from"], (dir / "source").string());
    const auto started = [](const nlohmann::json& row) {
        const fs::path run = row["run_dir"].get<std::string>();
        EXPECT_NE(run.filename().string().find("-warm-"), std::string::npos) << run;
        return nlohmann::json::parse(std::ifstream(run / "result.json"));
    };
    const auto ref = started(j["reference"]), variant = started(j["rows"][0]);
    EXPECT_EQ(ref["start"]["warm_from"], fs::absolute(dir / "source").string());
    EXPECT_NEAR(ref["initial_loading_kg"].get<double>(), m0, 1e-4 * m0);
    EXPECT_NEAR(variant["initial_loading_kg"].get<double>(), 1.5 * m0, 1e-3 * m0);

    const auto bad = runMixload({"study", "formulation", "--variant", "denser:rho=1.5", "--warm-from",
                                 (dir / "nothing").string(), "--out", (dir / "bad").string()});
    EXPECT_EQ(bad.rc, 2) << bad.err;
    EXPECT_NE(bad.err.find("warm-from"), std::string::npos) << bad.err;
    EXPECT_FALSE(fs::exists(dir / "bad"));
}

// The multi-fidelity pilot pairs the two studies' steady runs by variant (a run unsteady on one
// mesh, or missing from it, is left out), fits fine against coarse and says whether co-kriging
// would earn its place; a directory without a study is refused.
TEST(FormulationStudy, FidelityPilotPairsTheTwoMeshesRuns) {
    const fs::path out = scratchDir("fidelity");
    auto r = runMixload({"study", "fidelity", "--fine", MIXLOAD_TEST_DATA "/fidelity/fine", "--coarse", MIXLOAD_TEST_DATA "/fidelity/coarse",
                         "--out", (out / "p").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["pairs"], 9);
    EXPECT_NEAR(j["ratio"]["mean"].get<double>(), 1.15, 0.01);
    EXPECT_GT(j["fit"]["r2"].get<double>(), 0.99);
    EXPECT_EQ(j["verdict"].get<std::string>().rfind("earns its place", 0), 0u) << j["verdict"];
    EXPECT_NEAR(j["cost_ratio"].get<double>(), 1.0, 1e-12);
    EXPECT_TRUE(fs::exists(out / "p" / "fidelity.md"));
    r = runMixload({"study", "fidelity", "--fine", out.string(), "--coarse", MIXLOAD_TEST_DATA "/fidelity/coarse", "--out", (out / "q").string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("study.json"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out / "q"));
}
