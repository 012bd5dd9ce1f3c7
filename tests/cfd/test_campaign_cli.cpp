// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload campaign create | run | status | export` through the real executable: a real collapse
// campaign whose driver is killed with SIGKILL mid-run and then finishes every run exactly once,
// and bad ranges files (exit 2, one line naming the problem, no campaign left behind).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <fstream>
#include <set>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "post/foam_files.hpp"
#include "common/atomic_file.hpp"
#include "run/foam_runner.hpp"
#include "run/run_dir.hpp"
#include "store/ledger.hpp"

using namespace mixload::testing;
using mixload::readFile;
namespace fs = std::filesystem;

namespace {
fs::path rangesFile(const fs::path& dir, const std::string& name, const std::string& text) {
    const fs::path f = dir / (name + ".toml");
    std::ofstream(f) << text;
    return f;
}
}  // namespace

TEST(CampaignCli, CreateStatusExport) {
    const fs::path dir = scratchDir("campaign-cli");
    const auto ranges = rangesFile(dir, "r",
                                   "scene = \"collapse\"\n[aspect]\nmin = 0.5\nmax = 6\nunit = \"1\"\n"
                                   "[delta_mu]\nmin = 0.2\nmax = 0.5\nunit = \"1\"\n");
    auto r = runMixload({"campaign", "create", "c1", "--ranges", ranges.string(), "--design", "sobol",
                         "--n", "5", "--mesh", "10", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["points"], 5);
    EXPECT_TRUE(fs::exists(dir / "c1" / "ledger.sqlite"));

    r = runMixload({"campaign", "status", "c1", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto st = nlohmann::json::parse(r.out);
    EXPECT_EQ(st["counts"]["queued"], 5);
    EXPECT_TRUE(st["integrity_ok"].get<bool>());

    const fs::path csv = dir / "c1.csv";
    r = runMixload({"campaign", "export", "c1", "-o", csv.string(), "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    std::ifstream in(csv);
    std::string provenance, header, line;
    std::getline(in, provenance);
    std::getline(in, header);
    EXPECT_NE(provenance.find("design sobol"), std::string::npos) << provenance;
    EXPECT_EQ(header.rfind("index,aspect,delta_mu,scene_hash,status", 0), 0u) << header;
    int rows = 0;
    while (std::getline(in, line)) {
        ++rows;
        // Sobol in [0.5, 6]: the first point is the cube's centre.
        if (rows == 1) EXPECT_EQ(line.rfind("0,3.25,0.35,", 0), 0u) << line;
    }
    EXPECT_EQ(rows, 5);

    // The same name again is refused, and the first campaign is untouched.
    r = runMixload({"campaign", "create", "c1", "--ranges", ranges.string(), "--n", "3", "--dir",
                    dir.string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("exists"), std::string::npos) << r.err;
}

// The shipped similarity design of the calibrated scene: rho and I0 held at the scene's values, the
// feed and d sampled in their logs; the export carries the held inputs, so it trains a surrogate.
TEST(CampaignCli, ASimilarityDesignExportsEveryInput) {
    const fs::path dir = scratchDir("campaign-similarity");
    auto r = runMixload({"campaign", "create", "s", "--ranges", MIXLOAD_SOURCE_DIR "/data/campaigns/mixer-v2-ranges.toml", "--n", "8",
                         "--scene", "gcm250-v3", "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    const fs::path csv = dir / "s.csv";
    ASSERT_EQ(runMixload({"campaign", "export", "s", "-o", csv.string(), "--dir", dir.string()}).rc, 0);
    std::ifstream in(csv);
    std::string provenance, header, line;
    std::getline(in, provenance);
    std::getline(in, header);
    EXPECT_EQ(header.rfind("index,d,delta_mu,feed_kg_h,mu_s,rpm,scene_hash,i0,rho,status", 0), 0u) << header;
    int below = 0, rows = 0;
    while (std::getline(in, line)) {
        ++rows;
        std::vector<std::string> f;
        std::stringstream ss(line);
        for (std::string x; std::getline(ss, x, ',');) f.push_back(x);
        EXPECT_EQ(f.at(7), "0.28");
        EXPECT_EQ(f.at(8), "329.84");
        below += std::stod(f.at(3)) < 12.6;  // the geometric middle of 2.55 .. 64.1 kg/h
    }
    EXPECT_EQ(rows, 8);
    EXPECT_EQ(below, 4) << "a log-scaled Latin hypercube puts half its feeds below the geometric middle";
}

TEST(CampaignCli, BadRangesCreateNothing) {
    const fs::path dir = scratchDir("campaign-bad");
    struct Case {
        const char* text;
        const char* needle;
    } cases[] = {
        {"scene = \"mixer\"\n[rho]\nmin = 600\nmax = 250\nunit = \"kg/m3\"\n", "rho.min = 600"},
        {"scene = \"mixer\"\n[colour]\nmin = 1\nmax = 2\nunit = \"1\"\n", "parameter = colour"},
        {"scene = \"mixer\"\n[d]\nmin = 1e-4\nmax = 4e-4\n", "d.unit = (missing)"},
    };
    int k = 0;
    for (const auto& c : cases) {
        const auto f = rangesFile(dir, "bad" + std::to_string(k), c.text);
        const std::string name = "bad" + std::to_string(k++);
        const auto r = runMixload({"campaign", "create", name, "--ranges", f.string(), "--n", "4",
                                   "--dir", dir.string()});
        EXPECT_EQ(r.rc, 2) << r.err;
        EXPECT_NE(r.err.find(c.needle), std::string::npos) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(dir / name)) << "campaign directory left behind";
    }
}

namespace {
// Processes whose working directory lies under dir (solvers of a killed driver would show here).
std::vector<std::string> processesIn(const fs::path& dir) {
    std::vector<std::string> found;
    for (const auto& e : fs::directory_iterator("/proc")) {
        const std::string pid = e.path().filename().string();
        if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
        std::error_code ec;
        const auto cwd = fs::read_symlink(e.path() / "cwd", ec);
        if (!ec && cwd.string().rfind(dir.string(), 0) == 0) found.push_back(pid + " " + cwd.string());
    }
    return found;
}

// `mixload campaign run NAME --dir DIR` in a child process, its output discarded.
pid_t startDriver(const char* name, const fs::path& dir) {
    const pid_t pid = fork();
    if (pid == 0) {
        freopen("/dev/null", "w", stdout);
        freopen("/dev/null", "w", stderr);
        execl(MIXLOAD_EXE, MIXLOAD_EXE, "campaign", "run", name, "--dir", dir.c_str(), nullptr);
        _exit(127);
    }
    return pid;
}

// Whether a flow solver (not a meshing utility) runs in dir.
bool solverRunningIn(const fs::path& dir) {
    for (const auto& p : processesIn(dir)) {
        std::ifstream comm("/proc/" + p.substr(0, p.find(' ')) + "/comm");
        std::string name;
        std::getline(comm, name);
        if (name.find("nterFoa") != std::string::npos) return true;
    }
    return false;
}
}  // namespace

TEST(CampaignCli, DriverKilledWithSigkillFinishesEveryRunOnce) {
    const fs::path dir = fs::canonical(scratchDir("campaign-kill"));
    const auto ranges = rangesFile(dir, "r", "scene = \"collapse\"\n[aspect]\nmin = 1\nmax = 3\nunit = \"1\"\n");
    auto r = runMixload({"campaign", "create", "k", "--ranges", ranges.string(), "--n", "3", "--mesh",
                         "10", "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;

    const pid_t driver = startDriver("k", dir);
    ASSERT_GE(driver, 0);
    // Until its first solver runs: killed while a case is meshed, the driver leaves no case and no
    // slice, and a fixed sleep let a loaded machine kill it there (CI: 3 slices instead of 4).
    for (int i = 0; i < 300 && !solverRunningIn(dir); ++i) usleep(100000);
    ASSERT_TRUE(solverRunningIn(dir)) << "no solver started";
    kill(driver, SIGKILL);
    int st = 0;
    waitpid(driver, &st, 0);
    ASSERT_TRUE(WIFSIGNALED(st)) << "the driver ended before it was killed";
    // Its solver dies with it (SIGTERM from the kernel when its parent goes).
    // (up to 20 s: on a loaded machine a solver takes a while to handle its SIGTERM)
    for (int i = 0; i < 200 && !processesIn(dir).empty(); ++i) usleep(100000);
    EXPECT_TRUE(processesIn(dir).empty()) << processesIn(dir).front();
    // The dead driver's row still reads "running"; status tells it from a live one.
    r = runMixload({"campaign", "status", "k", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["counts"]["running"], 1) << r.out;
    EXPECT_EQ(nlohmann::json::parse(r.out)["driver_running"], false) << r.out;
    r = runMixload({"campaign", "status", "k", "--dir", dir.string()});
    EXPECT_NE(r.out.find("no driver is running"), std::string::npos) << r.out;

    r = runMixload({"campaign", "run", "k", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto out = nlohmann::json::parse(r.out);
    EXPECT_EQ(out["counts"]["done"], 3);
    EXPECT_EQ(out["counts"]["queued"], 0);
    EXPECT_EQ(out["counts"]["running"], 0);
    EXPECT_EQ(out["counts"]["failed"], 0);

    r = runMixload({"campaign", "status", "k", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_TRUE(nlohmann::json::parse(r.out)["integrity_ok"].get<bool>());
    // Exactly one finished directory per point: no temp, failed or duplicate cases.
    int dirs = 0, slices = 0;
    for (const auto& e : fs::directory_iterator(dir / "k" / "runs")) {
        ++dirs;
        const std::string name = e.path().filename().string();
        EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
        EXPECT_EQ(name.find(".failed"), std::string::npos) << name;
        ASSERT_TRUE(fs::exists(e.path() / "result.json")) << name;
        slices += nlohmann::json::parse(readFile(e.path() / "result.json")).value("slices", 0);
    }
    EXPECT_EQ(dirs, 3);
    // The killed process's time counts in its point's result, beside the one that finished it.
    EXPECT_EQ(slices, 4);
}

TEST(CampaignCli, SigtermStopsTheDriverAsItsDeadlineWould) {
    // SIGTERM (or Ctrl-C) asks the driver to stop: its solver is stopped, its point released (not
    // left "running" for the next driver to take as a death), and it exits 0; the next run finishes
    // the campaign and counts the stopped slice.
    const fs::path dir = fs::canonical(scratchDir("campaign-term"));
    const auto ranges = rangesFile(dir, "r", "scene = \"collapse\"\n[aspect]\nmin = 1\nmax = 3\nunit = \"1\"\n");
    auto r = runMixload({"campaign", "create", "t", "--ranges", ranges.string(), "--n", "2", "--mesh", "10",
                         "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    const pid_t driver = startDriver("t", dir);
    ASSERT_GE(driver, 0);
    // Until its first solver runs (a stop while a case is meshed leaves no case and no slice).
    for (int i = 0; i < 300 && !solverRunningIn(dir); ++i) usleep(100000);
    ASSERT_TRUE(solverRunningIn(dir)) << "no solver started";
    kill(driver, SIGTERM);
    int st = 0;
    waitpid(driver, &st, 0);
    ASSERT_TRUE(WIFEXITED(st)) << "killed by signal " << (WIFSIGNALED(st) ? WTERMSIG(st) : 0);
    EXPECT_EQ(WEXITSTATUS(st), 0);
    EXPECT_TRUE(processesIn(dir).empty());
    r = runMixload({"campaign", "status", "t", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["counts"]["running"], 0) << r.out;
    EXPECT_GE(nlohmann::json::parse(r.out)["counts"]["queued"], 1) << r.out;
    r = runMixload({"campaign", "run", "t", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["counts"]["done"], 2) << r.out;
    EXPECT_EQ(nlohmann::json::parse(r.out)["recovered"], 0) << "the stopped point was left running";
    int slices = 0;
    for (const auto& e : fs::directory_iterator(dir / "t" / "runs"))
        if (e.is_directory()) slices += nlohmann::json::parse(readFile(e.path() / "result.json")).value("slices", 0);
    EXPECT_EQ(slices, 3);
}

TEST(CampaignCli, MaxHoursStopsTheSolverAndRequeues) {
    const fs::path dir = scratchDir("campaign-hours");
    const auto ranges = rangesFile(dir, "r", "scene = \"collapse\"\n[aspect]\nmin = 1\nmax = 3\nunit = \"1\"\n");
    auto r = runMixload({"campaign", "create", "h", "--ranges", ranges.string(), "--n", "2", "--mesh",
                         "10", "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    // 0.0005 h = 1.8 s: the first run is stopped in the middle and given back to the queue.
    r = runMixload({"campaign", "run", "h", "--max-hours", "0.0005", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto out = nlohmann::json::parse(r.out);
    EXPECT_TRUE(out["stopped_at_max_hours"].get<bool>());
    EXPECT_LT(out["wall_seconds"].get<double>(), 30.0);
    EXPECT_EQ(out["counts"]["queued"], 2);
    EXPECT_EQ(out["counts"]["running"], 0);
    r = runMixload({"campaign", "export", "h", "-o", (dir / "h.csv").string(), "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    std::ifstream in(dir / "h.csv");
    std::string line;
    std::getline(in, line);
    std::getline(in, line);
    while (std::getline(in, line)) EXPECT_NE(line.find(",queued,0,"), std::string::npos) << line;
}

TEST(CampaignCli, ExtendAddsOnlyNewPoints) {
    const fs::path dir = scratchDir("campaign-extend");
    const auto ranges = rangesFile(dir, "r", "scene = \"collapse\"\n[aspect]\nmin = 1\nmax = 3\nunit = \"1\"\n");
    auto aspects = [&](const std::string& name) {
        const fs::path csv = dir / (name + ".csv");
        EXPECT_EQ(runMixload({"campaign", "export", name, "-o", csv.string(), "--dir", dir.string()}).rc, 0);
        std::ifstream in(csv);
        std::string line;
        std::getline(in, line);
        std::getline(in, line);
        std::vector<double> a;
        while (std::getline(in, line)) a.push_back(std::stod(line.substr(line.find(',') + 1)));
        return a;
    };
    for (const char* design : {"sobol", "lhs"}) {
        const std::string name = std::string("x-") + design;
        ASSERT_EQ(runMixload({"campaign", "create", name, "--ranges", ranges.string(), "--design", design,
                              "--n", "4", "--mesh", "10", "--dir", dir.string()}).rc, 0);
        const auto before = aspects(name);
        const auto r = runMixload({"campaign", "extend", name, "--n", "4", "--dir", dir.string()});
        ASSERT_EQ(r.rc, 0) << r.err;
        const auto after = aspects(name);
        ASSERT_EQ(after.size(), 8u);
        for (size_t i = 0; i < 4; ++i) EXPECT_DOUBLE_EQ(after[i], before[i]);  // old points kept
        if (std::string(design) == "sobol") {
            // GSL's sequence continues (dimension 1, the zero point skipped), mapped to [1, 3].
            const double u[8] = {0.5, 0.75, 0.25, 0.375, 0.875, 0.625, 0.125, 0.1875};
            for (size_t i = 0; i < 8; ++i) EXPECT_DOUBLE_EQ(after[i], 1 + 2 * u[i]) << i;
        } else {
            // The new points take the strata of the finer division the old ones leave free.
            std::set<int> strata;
            for (double a : after) strata.insert(static_cast<int>((a - 1) / 2 * 8));
            EXPECT_EQ(strata.size(), 8u);
        }
        EXPECT_EQ(std::set<double>(after.begin(), after.end()).size(), 8u) << "a point repeats";
    }
}

// One adaptive batch on a real campaign: refused (nothing added) before five runs have finished;
// then two points where the model of the finished runs is least sure, none repeating a design point.
TEST(CampaignCli, AdaptiveExtensionGoesWhereTheFinishedRunsSayLeast) {
    const fs::path dir = scratchDir("campaign-adaptive");
    const auto ranges = rangesFile(dir, "r", "scene = \"collapse\"\n[aspect]\nmin = 1\nmax = 3\nunit = \"1\"\n");
    ASSERT_EQ(runMixload({"campaign", "create", "a", "--ranges", ranges.string(), "--design", "sobol", "--n", "5", "--mesh", "10",
                          "--dir", dir.string()}).rc, 0);
    auto r = runMixload({"campaign", "extend", "a", "--n", "2", "--adaptive", "--dir", dir.string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("finished runs"), std::string::npos) << r.err;
    r = runMixload({"campaign", "status", "a", "--dir", dir.string(), "--json"});
    EXPECT_EQ(nlohmann::json::parse(r.out)["points"], 5);

    r = runMixload({"campaign", "run", "a", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    ASSERT_EQ(nlohmann::json::parse(r.out)["counts"]["done"], 5);
    r = runMixload({"campaign", "extend", "a", "--n", "2", "--adaptive", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["added"], 2);
    EXPECT_EQ(j["points"], 7);
    const auto& a = j["adaptive"];
    EXPECT_EQ(a["quantity"], "runout_star");
    EXPECT_EQ(a["finished_runs"], 5);
    ASSERT_EQ(a["picks"].size(), 2u);
    // The Sobol design (0.5, 0.75, 0.25, 0.375, 0.875 of [1, 3]) leaves its widest gaps at the ends.
    std::set<double> aspects{2.0, 2.5, 1.5, 1.75, 2.75};
    for (const auto& p : a["picks"]) {
        const double x = p["params"]["aspect"].get<double>();
        EXPECT_TRUE(x < 1.5 || x > 2.75) << x;
        EXPECT_TRUE(aspects.insert(x).second) << "repeats " << x;
        EXPECT_GT(p["sd_log"].get<double>(), 0.0);
    }
    // The queued picks are conditioned on: a second batch goes elsewhere.
    r = runMixload({"campaign", "extend", "a", "--n", "1", "--adaptive", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto again = nlohmann::json::parse(r.out)["adaptive"];
    EXPECT_EQ(again["pending_runs"], 2);
    EXPECT_TRUE(aspects.insert(again["picks"][0]["params"]["aspect"].get<double>()).second);
    EXPECT_EQ(again["criterion"], "variance");
    // The loo-weighted criterion through the CLI: the weight is recorded; without --adaptive, or
    // with an unknown criterion, nothing is added (exit 2).
    r = runMixload({"campaign", "extend", "a", "--n", "1", "--adaptive", "--criterion", "loo-weighted", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto weighted = nlohmann::json::parse(r.out)["adaptive"];
    EXPECT_EQ(weighted["criterion"], "loo-weighted");
    EXPECT_GE(weighted["picks"][0]["loo_weight"].get<double>(), 1.0);
    // A collapse campaign has no cost model: its picks say none, and per-core-hour is refused.
    EXPECT_TRUE(weighted["picks"][0]["core_hours"].is_null());
    EXPECT_FALSE(weighted["per_core_hour"].get<bool>());
    r = runMixload({"campaign", "extend", "a", "--n", "1", "--adaptive", "--per-core-hour", "--dir", dir.string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("per-core-hour"), std::string::npos) << r.err;
    for (const std::vector<std::string>& bad : {std::vector<std::string>{"--criterion", "loo-weighted"},
                                                std::vector<std::string>{"--per-core-hour"},
                                                std::vector<std::string>{"--adaptive", "--criterion", "nearest"}}) {
        std::vector<std::string> args{"campaign", "extend", "a", "--n", "1", "--dir", dir.string()};
        args.insert(args.end(), bad.begin(), bad.end());
        EXPECT_EQ(runMixload(args).rc, 2) << bad.back();
    }
    r = runMixload({"campaign", "status", "a", "--dir", dir.string(), "--json"});
    EXPECT_EQ(nlohmann::json::parse(r.out)["points"], 9);
}

TEST(CampaignCli, TheShippedThinPaddleCampaignIsNotRecreated) {
    // The README's regeneration command of the first campaign (gcm250: 4 mm paddles, snappy on 1 cm,
    // whose refined cells are 5 mm) asks for a paddle its mesh cannot cut: refused before any ledger
    // exists, naming the key. The shipped ledger stays as the record of what was run.
    const fs::path dir = scratchDir("campaign-regenerate");
    const std::string data = MIXLOAD_DATA_DIR;
    auto r = runMixload({"campaign", "create", "mixer-avicel", "--ranges",
                         data + "/campaigns/mixer-avicel-ranges.toml", "--design", "lhs", "--n", "40",
                         "--seed", "1", "--scene", "gcm250", "--method", "mrf", "--cell-size", "0.01",
                         "--initial-loading-kg", "0.03", "--end-time", "120", "--steady-tol", "0.01",
                         "--steady-flow-tol", "0.03", "--mesher", "snappy",
                         "--steady-window-residence", "0", "--numerics", "legacy",
                         "--dir", dir.string(), "--json"});
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("impeller.paddle_thickness_m = 0.004 m in scene gcm250"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "mixer-avicel"));
}

TEST(CampaignCli, WarmNearestStartsAPointFromTheNearestFinishedRun) {
    const fs::path dir = fs::canonical(scratchDir("campaign-warm"));
    const auto ranges = rangesFile(dir, "r", "scene = \"mixer\"\n[rpm]\nmin = 39\nmax = 60\nunit = \"rpm\"\n");
    auto r = runMixload({"campaign", "create", "w", "--ranges", ranges.string(), "--design", "sobol", "--n", "2",
                         "--scene", kV3At2cm, "--cell-size", "0.02", "--end-time", "0.05", "--protocol", "scene", "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = runMixload({"campaign", "run", "w", "--warm-nearest", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["counts"]["done"], 2);

    std::vector<nlohmann::json> results;
    for (const auto& e : fs::directory_iterator(dir / "w" / "runs"))
        if (fs::exists(e.path() / "result.json")) {
            std::ifstream in(e.path() / "result.json");
            results.push_back(nlohmann::json::parse(in));
        }
    ASSERT_EQ(results.size(), 2u);
    const auto& first = results[0]["start"].contains("warm_from") ? results[1] : results[0];
    const auto& second = results[0]["start"].contains("warm_from") ? results[0] : results[1];
    EXPECT_TRUE(first["start"].contains("deposit_kg")) << first["start"].dump();
    ASSERT_TRUE(second["start"].contains("warm_from")) << second["start"].dump();
    EXPECT_EQ(second["start"]["warm_from"].get<std::string>(), first["run_dir"].get<std::string>());
    // One step's feed apart at most (5 kg/h x the first step).
    EXPECT_NEAR(second["initial_loading_kg"].get<double>(), first["final_loading_kg"].get<double>(), 1e-4);
    EXPECT_GT(std::abs(second["initial_loading_kg"].get<double>() - first["initial_loading_kg"].get<double>()), 0.0);

    const fs::path csv = dir / "w.csv";
    ASSERT_EQ(runMixload({"campaign", "export", "w", "-o", csv.string(), "--dir", dir.string()}).rc, 0);
    std::ifstream in(csv);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    EXPECT_NE(text.find(",start,"), std::string::npos);
    EXPECT_NE(text.find(",deposit:"), std::string::npos) << text;
    EXPECT_NE(text.find(",warm:"), std::string::npos) << text;

    const auto cranges = rangesFile(dir, "c", "scene = \"collapse\"\n[aspect]\nmin = 1\nmax = 3\nunit = \"1\"\n");
    ASSERT_EQ(runMixload({"campaign", "create", "c", "--ranges", cranges.string(), "--n", "1", "--mesh", "10",
                          "--dir", dir.string()}).rc, 0);
    r = runMixload({"campaign", "run", "c", "--warm-nearest", "--dir", dir.string()});
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("warm-nearest"), std::string::npos) << r.err;
}

// A machine that comes back without the run directories still warm-starts: the finished run's
// kept final fields (fields.h5 beside the ledger) become the new point's start, powder and velocity.
TEST(CampaignCli, WarmNearestStartsFromKeptFieldsWhenTheRunDirectoryIsGone) {
    const fs::path dir = fs::canonical(scratchDir("campaign-warm-kept"));
    const auto ranges = rangesFile(dir, "r", "scene = \"mixer\"\n[rpm]\nmin = 39\nmax = 60\nunit = \"rpm\"\n");
    auto r = runMixload({"campaign", "create", "k", "--ranges", ranges.string(), "--design", "sobol", "--n", "1",
                         "--scene", kV3At2cm, "--cell-size", "0.02", "--end-time", "0.05", "--protocol", "scene", "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    ASSERT_EQ(runMixload({"campaign", "run", "k", "--warm-nearest", "--snapshots", "--dir", dir.string()}).rc, 0);
    const auto resultIn = [](const fs::path& runs) {
        for (const auto& e : fs::directory_iterator(runs))
            if (fs::exists(e.path() / "result.json")) {
                std::ifstream in(e.path() / "result.json");
                return nlohmann::json::parse(in);
            }
        return nlohmann::json();
    };
    const auto first = resultIn(dir / "k" / "runs");
    ASSERT_TRUE(first.contains("final_loading_kg")) << first.dump();
    fs::remove_all(dir / "k" / "runs");
    ASSERT_EQ(runMixload({"campaign", "extend", "k", "--n", "1", "--dir", dir.string()}).rc, 0);
    r = runMixload({"campaign", "run", "k", "--warm-nearest", "--snapshots", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["counts"]["done"], 2);
    const auto second = resultIn(dir / "k" / "runs");
    ASSERT_TRUE(second["start"].contains("warm_from")) << second["start"].dump();
    EXPECT_EQ(fs::path(second["start"]["warm_from"].get<std::string>()), dir / "k" / "warm" / "kept-k-0.h5");
    EXPECT_TRUE(second["start"].value("velocity", false)) << second["start"].dump();
    // The kept field is the run's last snapshot, its final time.
    EXPECT_NEAR(second["initial_loading_kg"].get<double>(), first["final_loading_kg"].get<double>(), 1e-4);

    // A kept file that cannot be read fails no point: the next one starts from its deposit, warned.
    fs::remove_all(dir / "k" / "runs");
    fs::resize_file(dir / "k" / "fields.h5", 1000);
    ASSERT_EQ(runMixload({"campaign", "extend", "k", "--n", "1", "--dir", dir.string()}).rc, 0);
    r = runMixload({"campaign", "run", "k", "--warm-nearest", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["counts"]["done"], 3) << r.out;
    EXPECT_NE(r.err.find("starts from its deposit"), std::string::npos) << r.err;
    EXPECT_TRUE(resultIn(dir / "k" / "runs")["start"].contains("deposit_kg"));
}

// A mixer campaign makes labels by default: its one tiny real run starts from the protocol's
// 0.05 kg deposit and records protocol and verdict (too short to settle, so no label, and it says
// why); a warm start on that campaign is refused before anything runs (exit 2).
TEST(CampaignCli, LabelProtocolRefusesAWarmStart) {
    const fs::path dir = fs::canonical(scratchDir("campaign-label"));
    const auto ranges = rangesFile(dir, "r", "scene = \"mixer\"\n[rpm]\nmin = 39\nmax = 60\nunit = \"rpm\"\n");
    auto r = runMixload({"campaign", "create", "l", "--ranges", ranges.string(), "--design", "sobol", "--n", "1",
                         "--scene", kV3At2cm, "--cell-size", "0.02", "--end-time", "0.05", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = runMixload({"campaign", "run", "l", "--warm-nearest", "--dir", dir.string()});
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("label-v1"), std::string::npos) << r.err;
    r = runMixload({"campaign", "status", "l", "--dir", dir.string(), "--json"});
    EXPECT_EQ(nlohmann::json::parse(r.out)["counts"]["queued"], 1) << r.out;

    r = runMixload({"campaign", "run", "l", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    nlohmann::json result;
    for (const auto& e : fs::directory_iterator(dir / "l" / "runs"))
        if (fs::exists(e.path() / "result.json")) {
            std::ifstream in(e.path() / "result.json");
            result = nlohmann::json::parse(in);
        }
    EXPECT_EQ(result.value("protocol", ""), "label-v1") << result.dump();
    EXPECT_DOUBLE_EQ(result["start"].value("deposit_kg", 0.0), 0.05) << result["start"].dump();
    EXPECT_FALSE(result.value("label", true));
    EXPECT_FALSE(result.value("not_label_because", "").empty()) << result.dump();
}

TEST(CampaignCli, AMixerRunStoppedAndResumedCountsBothSlices) {
    // A tiny mixer point stopped at --max-hours and finished by a second driver: its result, and the
    // ledger, count the time of both processes, not the last one's alone.
    const fs::path dir = scratchDir("campaign-slices");
    const auto ranges = rangesFile(dir, "r", "scene = \"mixer\"\n[rho]\nmin = 300\nmax = 400\nunit = \"kg/m3\"\n");
    auto r = runMixload({"campaign", "create", "s", "--ranges", ranges.string(), "--n", "1", "--scene", kGcm250At1cm,
                         "--cell-size", "0.01", "--end-time", "2", "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = runMixload({"campaign", "run", "s", "--max-hours", "0.002", "--dir", dir.string(), "--json"});  // 7.2 s
    ASSERT_EQ(r.rc, 0) << r.err;
    ASSERT_TRUE(nlohmann::json::parse(r.out)["stopped_at_max_hours"].get<bool>()) << r.out;
    // status says where the stopped point stands.
    r = runMixload({"campaign", "status", "s", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto unfinished = nlohmann::json::parse(r.out)["unfinished"];
    ASSERT_EQ(unfinished.size(), 1u) << r.out;
    EXPECT_EQ(unfinished[0]["index"], 0);
    EXPECT_GT(unfinished[0]["time_s"].get<double>(), 0.0);
    EXPECT_GT(unfinished[0]["loading_kg"].get<double>(), 0.0);
    EXPECT_EQ(unfinished[0]["attempt"], "first");
    // Failed once and claimed again, the point is a retry: its first attempt's directory is then left
    // behind, and status says so. Requeued, it is a first attempt in that directory again.
    {
        mixload::store::Ledger l(dir / "s" / "ledger.sqlite");
        const auto first = l.claimNext("s", 2, false);
        ASSERT_TRUE(first);
        l.markFailed(first->id, "a first attempt that failed", false);
        ASSERT_TRUE(l.claimNext("s", 2, false));
    }
    r = runMixload({"campaign", "status", "s", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["unfinished"][0]["attempt"], "first, left") << r.out;
    r = runMixload({"campaign", "status", "s", "--dir", dir.string()});
    EXPECT_NE(r.out.find("point 0 (first attempt, left behind by its retry)"), std::string::npos) << r.out;
    ASSERT_EQ(runMixload({"campaign", "requeue", "s", "--point", "0", "--dir", dir.string()}).rc, 0);
    r = runMixload({"campaign", "run", "s", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    ASSERT_EQ(nlohmann::json::parse(r.out)["counts"]["done"], 1) << r.out;
    fs::path run;
    for (const auto& e : fs::directory_iterator(dir / "s" / "runs"))
        if (e.is_directory()) run = e.path();
    const auto res = nlohmann::json::parse(readFile(run / "result.json"));
    std::cout << "slices " << res["slices"] << ": wall " << res["wall_seconds"] << " s, this process "
              << res["slice_wall_seconds"] << " s\n";
    EXPECT_EQ(res["slices"], 2);
    EXPECT_GT(res["wall_seconds"].get<double>(), res["slice_wall_seconds"].get<double>() + 4.0);
    EXPECT_GE(res["core_seconds"].get<double>(), res["wall_seconds"].get<double>() * 0.9);
    r = runMixload({"campaign", "export", "s", "-o", (dir / "s.csv").string(), "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(readFile(dir / "s.csv").find(",done,"), std::string::npos);
}

// A scene revision whose mesh is cell for cell the campaign's takes the campaign over: the unfinished
// point resumes in its directory (renamed to the new hash), the ledger names the new scene and the
// rebase. A revision whose mesh differs, or that changes another input, is refused and changes nothing.
TEST(CampaignCli, RebaseMovesACampaignOntoARevisionWithTheSameMesh) {
    const fs::path dir = fs::canonical(scratchDir("campaign-rebase"));
    const auto ranges = rangesFile(dir, "r", "scene = \"mixer\"\n[rho]\nmin = 300\nmax = 400\nunit = \"kg/m3\"\n");
    const std::string text = readFile(kGcm250At2cm);
    const auto revision = [&](const std::string& name, const std::string& from, const std::string& to) {
        std::string t = text;
        const auto at = t.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        t.replace(at, from.size(), to);
        const fs::path f = dir / (name + ".toml");
        std::ofstream(f) << t;
        return f.string();
    };
    const auto same = revision("same", "paddle_thickness_m = 0.0285", "paddle_thickness_m = 0.02851");
    const auto thicker = revision("thicker", "paddle_thickness_m = 0.0285", "paddle_thickness_m = 0.031");
    const auto faster = revision("faster", "\nfeed_kg_h = ", "\nfeed_kg_h = 1");
    auto r = runMixload({"campaign", "create", "b", "--ranges", ranges.string(), "--n", "1", "--scene", kGcm250At2cm,
                         "--cell-size", "0.02", "--end-time", "6", "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = runMixload({"campaign", "run", "b", "--max-hours", "0.0008", "--dir", dir.string(), "--json"});  // 2.9 s
    ASSERT_EQ(r.rc, 0) << r.err;
    ASSERT_TRUE(nlohmann::json::parse(r.out)["stopped_at_max_hours"].get<bool>()) << r.out;
    const auto hashOf = [&] {
        mixload::store::Ledger l(dir / "b" / "ledger.sqlite");
        return l.runs("b").at(0).params.value("scene_hash", std::string());
    };
    const std::string before = hashOf();
    ASSERT_TRUE(fs::is_directory(dir / "b" / "runs" / ("0-" + before)));
    r = runMixload({"campaign", "rebase", "b", "--scene", thicker, "--dir", dir.string()});
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("cell for cell"), std::string::npos) << r.err;
    r = runMixload({"campaign", "rebase", "b", "--scene", faster, "--dir", dir.string()});
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("feed_kg_h"), std::string::npos) << r.err;
    EXPECT_EQ(hashOf(), before);
    EXPECT_TRUE(fs::is_directory(dir / "b" / "runs" / ("0-" + before)));
    r = runMixload({"campaign", "rebase", "b", "--scene", same, "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["scene"], same);
    ASSERT_EQ(j["moved_run_dirs"].size(), 1u) << r.out;
    const std::string after = hashOf();
    EXPECT_NE(after, before);
    EXPECT_FALSE(fs::exists(dir / "b" / "runs" / ("0-" + before)));
    {
        mixload::store::Ledger l(dir / "b" / "ledger.sqlite");
        const auto base = l.campaign("b")->sceneJson;
        EXPECT_EQ(base["scene"], same);
        EXPECT_EQ(base["rebased"]["mesh_checksum"], j["mesh_checksum"]);
    }
    // The point resumes where it stood: two slices, one run directory, the new scene's hash.
    r = runMixload({"campaign", "run", "b", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    ASSERT_EQ(nlohmann::json::parse(r.out)["counts"]["done"], 1) << r.out;
    const auto res = nlohmann::json::parse(readFile(dir / "b" / "runs" / ("0-" + after) / "result.json"));
    EXPECT_EQ(res["slices"], 2);
    EXPECT_EQ(res["scene_hash"], after);
}

TEST(CampaignCli, APointWhoseRunDirectoryIsLostResumesFromItsKeptProgress) {
    // A mixer point stopped at --max-hours keeps its latest fields and counted time beside the
    // ledger (progress.h5); with its run directory gone (a machine that came back empty) the next
    // driver starts it from them, counts the lost slice, and drops the kept progress once it is done.
    const fs::path dir = fs::canonical(scratchDir("campaign-progress"));
    const auto ranges = rangesFile(dir, "r", "scene = \"mixer\"\n[rpm]\nmin = 100\nmax = 120\nunit = \"rpm\"\n");
    auto r = runMixload({"campaign", "create", "p", "--ranges", ranges.string(), "--n", "1", "--scene", kGcm250At2cm,
                         "--cell-size", "0.02", "--end-time", "6", "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    // Slices of 5.4 s until one has written a time to keep (a loaded machine may need several).
    for (int slice = 0; slice < 6 && !fs::exists(dir / "p" / "progress.h5"); ++slice) {
        r = runMixload({"campaign", "run", "p", "--max-hours", "0.0015", "--dir", dir.string(), "--json"});
        ASSERT_EQ(r.rc, 0) << r.err;
        ASSERT_TRUE(nlohmann::json::parse(r.out)["stopped_at_max_hours"].get<bool>()) << r.out;
    }
    ASSERT_TRUE(fs::exists(dir / "p" / "progress.h5")) << r.err;
    std::string lost;
    for (const auto& e : fs::directory_iterator(dir / "p" / "runs"))
        if (e.is_directory()) lost = e.path().filename().string();
    fs::remove_all(dir / "p" / "runs");
    r = runMixload({"campaign", "run", "p", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    ASSERT_EQ(nlohmann::json::parse(r.out)["counts"]["done"], 1) << r.out;
    const auto res = nlohmann::json::parse(readFile(dir / "p" / "runs" / lost / "result.json"));
    EXPECT_EQ(res["start"].value("continues_run_dir", ""), lost) << res["start"].dump();
    EXPECT_GT(res["start"].value("source_time_s", 0.0), 0.0) << res["start"].dump();
    // The flow run on the point before (what `campaign status` and its forecast count): the lost
    // run began the point, so it is the kept time.
    EXPECT_NEAR(res["start"].value("flow_before_s", -1.0), res["start"]["source_time_s"].get<double>(), 1e-9)
        << res["start"].dump();
    EXPECT_TRUE(res["start"].value("velocity", false)) << res["start"].dump();
    EXPECT_GE(res["slices"].get<int>(), 2);
    EXPECT_GT(res["wall_seconds"].get<double>(), res["slice_wall_seconds"].get<double>() + 4.0);
    EXPECT_TRUE(res["start"]["first_start"].contains("deposit_kg")) << "the lost run began at its deposit: " << res["start"].dump();
    // The steady test's history came along: the new run's monitor began with the lost run's
    // samples, shifted to end at its own time 0.
    EXPECT_GT(res["start"].value("monitor_history_s", 0.0), 0.0) << res["start"].dump();
    const auto seeded = mixload::post::readFunctionObjectState(
        dir / "p" / "runs" / lost / "0" / "uniform" / "functionObjects" / "functionObjectProperties", "loading");
    const auto& t = seeded.at("sampleTimes");
    ASSERT_GE(t.size(), 3u);
    EXPECT_LT(t.front(), -0.5);
    EXPECT_LE(t.back(), 1e-9);
    EXPECT_GT(t.back(), -0.5);
    EXPECT_LE(seeded.at("sampleOutflows").back(), 1e-9);  // the samples are written to 10 digits
    EXPECT_FALSE(fs::exists(dir / "p" / "progress.h5"));
    r = runMixload({"campaign", "export", "p", "-o", (dir / "p.csv").string(), "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_NE(readFile(dir / "p.csv").find(",continued:deposit:"), std::string::npos) << readFile(dir / "p.csv");
}

TEST(CampaignCli, ASliceLeftOpenByAKilledProcessEndsAtItsLastLogWrite) {
    // The slice of a process killed mid-run has a start and no end: the next process closes it at
    // the case's last log write, its core seconds that time on its ranks.
    const fs::path dir = scratchDir("slices-killed");
    const double now = std::chrono::duration<double>(fs::file_time_type::clock::now().time_since_epoch()).count();
    std::ofstream(dir / "slices.json") << nlohmann::json::array({{{"start_file_clock_s", now - 100.0}, {"np", 2}, {"open", true}}}).dump();
    std::ofstream(dir / "log.interFoam") << "Time = 1\n";
    fs::last_write_time(dir / "log.interFoam", fs::file_time_type::clock::now() - std::chrono::seconds(40));
    mixload::run::RunSlices slices(dir, 1);
    const auto total = slices.close(10.0, 10.0);
    EXPECT_EQ(total["slices"], 2);
    EXPECT_NEAR(total["wall_seconds"].get<double>(), 60.0 + 10.0, 1.0);
    EXPECT_NEAR(total["core_seconds"].get<double>(), 2 * 60.0 + 10.0, 2.0);
}

TEST(CampaignCli, AParallelRunKilledAndResumedSeriallyContinuesFromItsRanksTimes) {
    // A run on two ranks killed before it reconstructed its newest times, and cut short on rank 1
    // (made by hand from a finished run, so the test does not hang on a deadline's timing): the
    // next slice, serial, sets aside what not every rank wrote whole, reconstructs the rest, drops
    // the two-rank decomposition, and continues from there, not from the last reconstructed time.
    const fs::path dir = fs::canonical(scratchDir("mixer-np2-resume"));
    const fs::path run = dir / "m";
    const std::vector<std::string> args{"mixer", "--scene", kGcm250At2cm, "--cell-size", "0.02", "--rpm", "110",
                                        "--end-time", "1.3", "--out", run.string(), "--json"};
    auto withNp = [&](const char* np) {
        auto a = args;
        a.insert(a.end(), {"--np", np});
        return runMixload(a);
    };
    auto r = withNp("2");
    ASSERT_EQ(r.rc, 0) << r.err;
    std::vector<double> times;
    for (const auto& e : fs::directory_iterator(run / "processor0"))
        if (e.is_directory() && e.path().filename() != "constant") times.push_back(std::stod(e.path().filename().string()));
    std::sort(times.begin(), times.end());
    ASSERT_GE(times.size(), 4u) << "0, two writes and the end";
    const double cut = times.back(), resumeAt = times[times.size() - 2];
    fs::remove(run / "result.json");
    for (const double t : {cut, resumeAt}) {
        const fs::path reconstructed = mixload::run::latestTimeDir(run);
        ASSERT_NEAR(std::stod(reconstructed.filename().string()), t, 1e-9);
        fs::remove_all(reconstructed);
    }
    const fs::path cutDir = mixload::run::latestTimeDir(run / "processor1");
    fs::resize_file(cutDir / "alpha.powder", fs::file_size(cutDir / "alpha.powder") / 3);
    r = withNp("1");
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_FALSE(fs::exists(run / "processor0"));
    EXPECT_TRUE(nlohmann::json::parse(r.out)["resumed"].get<bool>());
    const std::string log = readFile(run / "log.interFoam");
    const auto loop = log.rfind("Starting time loop");
    ASSERT_NE(loop, std::string::npos);
    const double first = std::atof(log.c_str() + log.find("Time = ", loop) + 7);
    EXPECT_GT(first, resumeAt);
    EXPECT_LT(first, cut);
}

TEST(CampaignCli, AHalfWrittenLatestTimeIsSetAsideAndTheRunResumesBeforeIt) {
    // Finished runs (a collapse, binary mixer fields) have no partial time. A latest time with a
    // truncated field, or one missing a field the time before it has, is set aside; the run then
    // resumes from the time before and finishes (a killed solver's half-written time made the
    // kill test's resumed run fail and retry in another directory).
    const fs::path dir = scratchDir("partial-time");
    auto r = runMixload({"collapse", "--material", "quartz", "--aspect", "2", "--cells-per-length", "8", "--out",
                         (dir / "c").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_FALSE(mixload::run::setAsidePartialTime(dir / "c"));
    r = runMixload({"mixer", "--scene", kGcm250At1cm, "--cell-size", "0.01", "--end-time", "0.05", "--out", (dir / "m").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_FALSE(mixload::run::setAsidePartialTime(dir / "m"));

    const fs::path last = mixload::run::latestTimeDir(dir / "c");
    fs::resize_file(last / "U", fs::file_size(last / "U") / 2);
    const auto aside = mixload::run::setAsidePartialTime(dir / "c");
    ASSERT_TRUE(aside);
    EXPECT_FALSE(fs::exists(last));
    EXPECT_TRUE(fs::exists(*aside / "U"));
    const fs::path before = mixload::run::latestTimeDir(dir / "c");
    EXPECT_NE(before, last);
    fs::remove(before / "p_rgh");
    EXPECT_TRUE(mixload::run::setAsidePartialTime(dir / "c"));
    EXPECT_FALSE(fs::exists(before));
    EXPECT_FALSE(mixload::run::setAsidePartialTime(dir / "c"));

    // In a campaign: a collapse stopped at --max-hours, its latest time cut short as a kill would
    // leave it, finishes in its own directory on the first attempt.
    const auto ranges = rangesFile(dir, "r", "scene = \"collapse\"\n[aspect]\nmin = 1\nmax = 3\nunit = \"1\"\n");
    r = runMixload({"campaign", "create", "p", "--ranges", ranges.string(), "--n", "1", "--mesh", "10", "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = runMixload({"campaign", "run", "p", "--max-hours", "0.0008", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    ASSERT_TRUE(nlohmann::json::parse(r.out)["stopped_at_max_hours"].get<bool>()) << r.out;
    fs::path run;
    for (const auto& e : fs::directory_iterator(dir / "p" / "runs"))
        if (e.is_directory()) run = e.path();
    const fs::path cut = mixload::run::latestTimeDir(run);
    ASSERT_FALSE(cut.empty()) << "the run wrote no time before its deadline";
    fs::resize_file(cut / "alpha.powder", fs::file_size(cut / "alpha.powder") / 3);
    r = runMixload({"campaign", "run", "p", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["counts"]["done"], 1);
    int dirs = 0;
    for (const auto& e : fs::directory_iterator(dir / "p" / "runs")) dirs += e.is_directory();
    EXPECT_EQ(dirs, 1);  // no retry directory
    EXPECT_TRUE(fs::exists(run / "result.json"));
}

TEST(CampaignCli, ARunWhoseTimesGrewDigitsResumesFromItsLatestTime) {
    // v2's point 12 wrote 74.68951163209499 (OpenFOAM adds digits as write times drift) and its
    // next slice failed at once: v1912 looked for 74.68951163/p_rgh, the failure counted as an
    // attempt, and the retry started over in a new directory, 75 s of flow lost. A finished
    // collapse is given a later time whose 16-digit name v1912's search misses (its 18- and
    // 17-digit names agree); the solver must start from it (past the end time: it reads the
    // fields and stops).
    const fs::path dir = scratchDir("time-digits");
    const auto r = runMixload({"collapse", "--material", "quartz", "--aspect", "2", "--cells-per-length", "8", "--out",
                               (dir / "c").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const fs::path last = mixload::run::latestTimeDir(dir / "c");
    const double end = mixload::run::latestTime(dir / "c");
    const auto digits = [](double x, int p) {
        std::ostringstream o;
        o.precision(p);
        o << x;
        return o.str();
    };
    std::string name;
    for (int k = 1; name.empty() && k < 100000; ++k) {
        const double x = std::stod(digits(end * 1.01 + k * 1.37e-13, 16));
        if (digits(x, 18) == digits(x, 17) && digits(x, 16) != digits(x, 17) && digits(x, 16) != digits(x, 15))
            name = digits(x, 16);
    }
    ASSERT_FALSE(name.empty());
    fs::copy(last, dir / "c" / name, fs::copy_options::recursive);
    mixload::run::SolverRun s;
    s.caseDir = dir / "c";
    EXPECT_NO_THROW(mixload::run::runSolver(s));
    const std::string log = readFile(dir / "c" / "log.interFoam");
    EXPECT_NE(log.find("Create mesh for time = " + name), std::string::npos) << name;
    EXPECT_NE(readFile(dir / "c" / "system" / "controlDict").find("timePrecision 16;"), std::string::npos);
    EXPECT_EQ(mixload::run::fitTimePrecision(dir / "c"), 16);  // once raised, left as it is
    // Raised for a later time since set aside, 18 digits would print 17 where the name has 16:
    // the precision comes back down to one that names the latest time as written.
    const fs::path dict = dir / "c" / "system" / "controlDict";
    std::string text = readFile(dict);
    text.replace(text.find("timePrecision 16;"), 17, "timePrecision 18;");
    mixload::writeFileAtomic(dict, text);
    const int p = mixload::run::fitTimePrecision(dir / "c");
    EXPECT_LT(p, 18);
    EXPECT_EQ(digits(mixload::run::latestTime(dir / "c"), p), mixload::run::latestTimeDir(dir / "c").filename().string());
}

TEST(CampaignCli, RequeueGivesAFailedPointItsFirstAttemptBack) {
    // A point whose resume failed (an attempt counted) goes back to its first attempt's scene and
    // directory once the cause is mended; done and unknown points are refused, the ledger unchanged.
    const fs::path dir = scratchDir("requeue");
    const auto ranges = rangesFile(dir, "r", "scene = \"collapse\"\n[aspect]\nmin = 1\nmax = 3\nunit = \"1\"\n");
    auto r = runMixload({"campaign", "create", "q", "--ranges", ranges.string(), "--n", "2", "--mesh", "10", "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    {
        mixload::store::Ledger l(dir / "q" / "ledger.sqlite");
        const auto first = l.claimNext("q", 2, false);
        ASSERT_TRUE(first);
        l.markFailed(first->id, "resume failed at once", false);
        const auto second = l.claimNext("q", 2, false, l.runs("q").at(1).id);
        ASSERT_TRUE(second);
        l.markDone(second->id, nlohmann::json{{"runout_star", 1.0}}, 1, 1, "");
    }
    r = runMixload({"campaign", "requeue", "q", "--point", "1", "--dir", dir.string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("point"), std::string::npos) << r.err;
    r = runMixload({"campaign", "requeue", "q", "--point", "7", "--dir", dir.string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("0-1"), std::string::npos) << r.err;
    r = runMixload({"campaign", "requeue", "q", "--point", "0", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["before"]["attempts"], 1);
    EXPECT_EQ(j["before"]["error"], "resume failed at once");
    mixload::store::Ledger l(dir / "q" / "ledger.sqlite");
    const auto runs = l.runs("q");
    EXPECT_EQ(runs.at(0).status, "queued");
    EXPECT_EQ(runs.at(0).attempts, 0);
    EXPECT_TRUE(runs.at(0).error.empty());
    EXPECT_EQ(runs.at(1).status, "done");
}
