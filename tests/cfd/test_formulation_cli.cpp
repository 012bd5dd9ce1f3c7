// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload study formulation` on tiny real runs: the reference and a variant run, the table and
// the plot are written, a run without a steady verdict gets no pass or fail, and a variant the
// scene refuses stops the study before any run; a study started warm from a run.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "common/atomic_file.hpp"

using namespace mixload::testing;
namespace fs = std::filesystem;

TEST(FormulationStudy, RunsTheReferenceAndEachVariantAndJudgesOnlySteadyRuns) {
    const fs::path out = scratchDir("formulation") / "study";
    const std::string model = std::string(MIXLOAD_DATA_DIR) + "/models/mixer-loading-kriging.json";
    const auto r = runMixload({"study", "formulation", "--variant", "denser:rho=1.5,mu_s=0.9", "--scene", kGcm250At1cm, "--cell-size", "0.01",
                               "--end-time", "0.05", "--model", model, "--out", out.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["rows"].size(), 1u);
    const auto& row = j["rows"][0];
    EXPECT_EQ(row["verdict"], "open: not steady");
    EXPECT_EQ(j["open"], 1);
    // The surrogate's Fig. 7 is drawn before any full run is steady: five curves through (1, 1),
    // mu_d's without the factors that take it below mu_s (0.44 x 0.70 < 0.31).
    ASSERT_TRUE(j.contains("fig7")) << r.out;
    EXPECT_TRUE(j["fig7"]["parameters"].empty());
    const auto& curves = j["fig7"]["model"]["parameters"];
    ASSERT_EQ(curves.size(), 5u);
    for (const auto& c : curves) {
        bool atOne = false;
        for (const auto& xy : c["points"])
            if (std::abs(xy[0].get<double>() - 1) < 1e-12) atOne = std::abs(xy[1].get<double>() - 1) < 1e-12;
        EXPECT_TRUE(atOne) << c["parameter"];
        EXPECT_TRUE(std::isfinite(c["slope"].get<double>())) << c["parameter"];
        if (c["parameter"] == "mu_d") EXPECT_GT(c["points"][0][0].get<double>(), 0.70);
        if (c["parameter"] == "rho") EXPECT_EQ(c["points"].size(), 61u);
    }
    const std::string fig7 = mixload::readFile(out / "fig7.md");
    EXPECT_NE(fig7.find("| rho | 0 | - |"), std::string::npos) << fig7;
    EXPECT_TRUE(fs::exists(out / "fig7.png"));
    // A model file that is not one is refused before any run.
    const auto bad = runMixload({"study", "formulation", "--variant", "denser:rho=1.5", "--model", (out / "table.md").string(),
                                 "--out", (out.parent_path() / "bad").string()});
    EXPECT_EQ(bad.rc, 2) << bad.err;
    EXPECT_FALSE(fs::exists(out.parent_path() / "bad"));
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
    const auto again = runMixload({"study", "formulation", "--variant", "denser:rho=1.5,mu_s=0.9", "--scene", kGcm250At1cm, "--cell-size",
                                   "0.01", "--end-time", "0.05", "--out", out.string(), "--json"});
    ASSERT_EQ(again.rc, 0) << again.err;
    EXPECT_EQ(nlohmann::json::parse(again.out)["rows"][0]["loading_kg"], row["loading_kg"]);
}

TEST(FormulationStudy, StopsAtMaxHoursAndTheSameCommandResumes) {
    // A six-level Fig. 7 is tens of core-hours: the study runs in slices. Stopped, its runs are
    // open (not failed, exit 0) and the same command finishes them.
    const fs::path out = scratchDir("formulation-slices") / "study";
    const std::vector<std::string> args{"study", "formulation", "--variant", "denser:rho=1.2", "--scene", kGcm250At2cm, "--cell-size", "0.02",
                                        "--end-time", "0.05", "--out", out.string(), "--json"};
    auto sliced = args;
    sliced.insert(sliced.end(), {"--max-hours", "0.00001"});
    auto r = runMixload(sliced);
    ASSERT_EQ(r.rc, 0) << r.err;
    auto j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(j["stopped_at_max_hours"].get<bool>()) << r.out;
    EXPECT_EQ(j["unfinished"], 2);
    EXPECT_EQ(j["rows"][0]["verdict"].get<std::string>().rfind("open: not finished", 0), 0u) << j["rows"][0];
    EXPECT_NE(mixload::readFile(out / "table.md").find("M = not finished"), std::string::npos);
    r = runMixload(args);
    ASSERT_EQ(r.rc, 0) << r.err;
    j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["unfinished"], 0);
    EXPECT_TRUE(j["reference"].contains("loading_kg")) << r.out;
    EXPECT_TRUE(j["rows"][0].contains("loading_kg")) << r.out;
    EXPECT_EQ(runMixload({"study", "formulation", "--variant", "x:rho=1.2", "--max-hours", "-1", "--out", out.string()}).rc, 2);
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
    const auto src = runMixload({"mixer", "--scene", kGcm250At1cm, "--cell-size", "0.01", "--end-time", "0.05", "--out",
                                 (dir / "source").string(), "--json"});
    ASSERT_EQ(src.rc, 0) << src.err;
    const double m0 = nlohmann::json::parse(src.out)["final_loading_kg"].get<double>();
    const auto r = runMixload({"study", "formulation", "--variant", "denser:rho=1.5", "--scene", kGcm250At1cm,
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
    // Two meshes that cut different paddles are two impellers, not two resolutions: refused.
    auto other = nlohmann::json::parse(mixload::readFile(MIXLOAD_TEST_DATA "/fidelity/coarse/study.json"));
    other["reference"]["impeller"]["paddle_thickness_m"] = 0.0282;
    fs::create_directories(out / "thick");
    std::ofstream(out / "thick" / "study.json") << other.dump();
    r = runMixload({"study", "fidelity", "--fine", MIXLOAD_TEST_DATA "/fidelity/fine", "--coarse", (out / "thick").string(),
                    "--out", (out / "t").string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("another impeller"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out / "t"));
}
