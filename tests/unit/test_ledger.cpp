// SPDX-License-Identifier: GPL-3.0-or-later
// The SQLite run ledger: queue semantics, retries, extensions, and a writer killed with SIGKILL in
// the middle of its transactions.
#include <gtest/gtest.h>

#include <cmath>
#include <csignal>
#include <map>
#include <filesystem>
#include <set>
#include <sys/wait.h>
#include <unistd.h>

#include "store/ledger.hpp"
#include "campaign/campaign.hpp"
#include "campaign/campaign_table.hpp"
#include "table.hpp"
#include "studies/fidelity_pilot.hpp"
#include "common/atomic_file.hpp"
#include "common/input_error.hpp"

using namespace mixload::store;
namespace fs = std::filesystem;

namespace {
fs::path freshLedger(const std::string& name) {
    const fs::path dir = fs::temp_directory_path() / ("mixload-ledger-" + name + "-" + std::to_string(getpid()));
    fs::remove_all(dir);
    return dir / "ledger.sqlite";
}

CampaignInfo info(const std::string& name) {
    CampaignInfo c;
    c.name = name;
    c.scene = "collapse";
    c.sceneHash = "abc";
    c.sceneJson = {{"aspect", 2}};
    c.rangesToml = "scene = \"collapse\"\n";
    c.design = "lhs";
    c.seed = 7;
    c.mixloadVersion = "test";
    c.gitCommit = "none";
    return c;
}

std::vector<nlohmann::json> points(int n) {
    std::vector<nlohmann::json> p;
    for (int i = 0; i < n; ++i) p.push_back({{"aspect", 1.0 + i}});
    return p;
}
}  // namespace

TEST(Ledger, QueueClaimFinishRetry) {
    Ledger l(freshLedger("queue"));
    l.createCampaign(info("c"), points(3));
    EXPECT_THROW(l.createCampaign(info("c"), points(1)), std::runtime_error);
    EXPECT_EQ(l.status("c")["queued"], 3);

    auto a = l.claimNext("c", 2, false);
    ASSERT_TRUE(a);
    EXPECT_EQ(a->index, 0);
    EXPECT_EQ(a->attempts, 1);
    l.markDone(a->id, {{"runout_star", 2.2}}, 10.0, 20.0, "/tmp/x");

    auto b = l.claimNext("c", 2, false);
    ASSERT_TRUE(b);
    EXPECT_EQ(b->index, 1);
    l.markFailed(b->id, "solver diverged", /*failed=*/false);  // one more try
    auto b2 = l.claimNext("c", 2, false);
    ASSERT_TRUE(b2);
    EXPECT_EQ(b2->index, 1);
    EXPECT_EQ(b2->attempts, 2);
    l.markFailed(b2->id, "solver diverged again", /*failed=*/true);

    auto c = l.claimNext("c", 2, false);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->index, 2);
    EXPECT_FALSE(l.claimNext("c", 2, false));  // only a running one is left
    EXPECT_TRUE(l.claimNext("c", 2, true));    // a new driver may take it over
    EXPECT_FALSE(l.claimNext("c", 2, true));   // attempts exhausted

    const auto runs = l.runs("c");
    ASSERT_EQ(runs.size(), 3u);
    EXPECT_EQ(runs[0].status, "done");
    EXPECT_DOUBLE_EQ(runs[0].result["runout_star"], 2.2);
    EXPECT_EQ(runs[0].runDir, "/tmp/x");
    EXPECT_EQ(runs[1].status, "failed");
    EXPECT_EQ(runs[1].error, "solver diverged again");
    EXPECT_TRUE(l.integrityOk());
}

TEST(Ledger, ExtensionAppendsAndRequeue) {
    const auto file = freshLedger("extend");
    {
        Ledger l(file);
        l.createCampaign(info("c"), points(2));
        l.claimNext("c", 3, false);
    }
    Ledger l(file);  // reopened: the claimed run is still marked running
    EXPECT_EQ(l.status("c")["running"], 1);
    EXPECT_EQ(l.requeueRunning("c"), 1);
    l.addPoints("c", points(3));
    const auto runs = l.runs("c");
    ASSERT_EQ(runs.size(), 5u);
    for (int i = 0; i < 5; ++i) EXPECT_EQ(runs[i].index, i);
    EXPECT_EQ(l.status("c")["queued"], 5);
    ASSERT_TRUE(l.campaign("c"));
    EXPECT_EQ(l.campaign("c")->seed, 7u);
    EXPECT_FALSE(l.campaign("nope"));
}

TEST(Ledger, SurvivesSigkillDuringWrites) {
    // A child claims and finishes runs as fast as it can; the parent kills it with SIGKILL in the
    // middle. Reopened, the database is intact and every run is in one consistent state.
    const auto file = freshLedger("kill");
    {
        Ledger l(file);
        l.createCampaign(info("c"), points(20000));
    }
    const pid_t child = fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        Ledger l(file);
        while (auto r = l.claimNext("c", 5, true))
            l.markDone(r->id, {{"runout_star", r->index * 0.5}}, 1.0, 1.0, "dir");
        _exit(0);
    }
    usleep(300000);
    kill(child, SIGKILL);
    int st = 0;
    waitpid(child, &st, 0);
    ASSERT_TRUE(WIFSIGNALED(st)) << "the child finished before it was killed: make the job longer";

    Ledger l(file);
    EXPECT_TRUE(l.integrityOk());
    int done = 0, running = 0;
    for (const auto& r : l.runs("c")) {
        if (r.status == "done") {
            ++done;
            EXPECT_DOUBLE_EQ(r.result["runout_star"].get<double>(), r.index * 0.5);
            EXPECT_EQ(r.attempts, 1);
        } else if (r.status == "running") {
            ++running;
        } else {
            EXPECT_EQ(r.status, "queued");
            EXPECT_EQ(r.attempts, 0);
        }
    }
    EXPECT_GT(done, 0);
    EXPECT_LE(running, 1);  // at most the one in flight when the signal came
    EXPECT_EQ(l.requeueRunning("c"), running);
    for (const auto& r : l.runs("c"))
        if (r.status == "queued") EXPECT_EQ(r.attempts, 0) << "an interrupted attempt was counted";
}

namespace {
// A Sobol mixer campaign of n points on the calibrated scene, created in a fresh directory.
mixload::experiments::CampaignSpec sobolMixerCampaign(const std::string& name, const fs::path& dir, int n,
                                                      const std::string& rangesToml) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path ranges = dir / "r.toml";
    mixload::writeFileAtomic(ranges, rangesToml);
    mixload::experiments::CampaignSpec spec;
    spec.place = {name, dir.string()};
    spec.ranges = ranges.string();
    spec.design = "sobol";
    spec.n = n;
    spec.scene = "gcm250-v3";
    mixload::experiments::createCampaign(spec);
    return spec;
}

// Speed and feed over the user's ranges: the box the tests below design in.
const std::string kRpmFeedRanges =
    "scene = \"mixer\"\n[rpm]\nmin = 39\nmax = 254\nunit = \"rpm\"\n[feed_kg_h]\nmin = 5\nmax = 45\nunit = \"kg/h\"\n";
}  // namespace

// Replicates of a mixer campaign's finished points, and the label noise their pairs give. The
// results are written into the ledger by hand: this checks the bookkeeping (which points, which
// deposits, which pairs), not a solver.
TEST(Ledger, ReplicatesAndTheirNoise) {
    namespace ex = mixload::experiments;
    const fs::path dir = fs::temp_directory_path() / ("mixload-replicates-" + std::to_string(::getpid()));
    const auto spec = sobolMixerCampaign("rep", dir, 6, kRpmFeedRanges);
    EXPECT_THROW(ex::replicateCampaign(spec.place, 2, 0.5), mixload::InputError);  // nothing finished yet
    {
        Ledger l(spec.place.ledger());
        for (int i = 0; i < 4; ++i) {
            const auto r = l.claimNext("rep", 2, false);
            ASSERT_TRUE(r);
            l.markDone(r->id, {{"loading_kg", 0.1 * (r->index + 1)}, {"steady", true}}, 1, 1, "/x");
        }
    }
    const auto j = ex::replicateCampaign(spec.place, 2, 0.5);
    ASSERT_EQ(j["added"], 2);
    EXPECT_EQ(j["points"], 8);
    std::set<int> of;
    for (const auto& r : j["replicates"]) {
        EXPECT_NEAR(r["initial_loading_kg"].get<double>(), 0.5 * r["loading_kg"].get<double>(), 0.0005);
        of.insert(r["of_index"].get<int>());
    }
    EXPECT_EQ(of.size(), 2u);
    // The same call again adds nothing new for points already replicated from that deposit.
    EXPECT_EQ(ex::replicateCampaign(spec.place, 2, 0.5)["added"], 0);
    EXPECT_TRUE(ex::campaignNoise(spec.place)["run_noise"].is_null());
    {
        // The replicates finish 2% above their points' loadings.
        Ledger l(spec.place.ledger());
        std::map<std::string, double> m;
        for (const auto& r : l.runs("rep"))
            if (r.status == "done") m[r.params["rpm"].dump()] = r.result["loading_kg"].get<double>();
        // The first replicate's mesh laid half its deposit, the second's 5% more than asked.
        double laid = 0.5;
        while (auto r = l.claimNext("rep", 2, false)) {
            if (!r->params.contains("initial_loading_kg")) continue;
            const nlohmann::json start{{"deposit_kg", r->params["initial_loading_kg"]},
                                       {"laid_kg", laid * r->params["initial_loading_kg"].get<double>()}};
            l.markDone(r->id, {{"loading_kg", 1.02 * m.at(r->params["rpm"].dump())}, {"steady", true}, {"start", start}}, 1, 1, "/x");
            laid = 1.05;
        }
    }
    const auto noise = ex::campaignNoise(spec.place);
    EXPECT_EQ(noise["n"], 2);
    std::multiset<bool> far;
    for (const auto& p : noise["pairs"]) far.insert(p["laid_far_from_asked"].get<bool>());
    EXPECT_EQ(far, (std::multiset<bool>{false, true}));
    EXPECT_NEAR(noise["run_noise"].get<double>(), 0.02 / 1.01 / std::sqrt(2.0), 1e-9);
    // The surrogates' table of the campaign keeps its design points only: a replicate would count
    // its point twice, in training or in a hold-out.
    nlohmann::json provenance;
    const auto table = ex::campaignTable("rep", dir.string(), provenance);
    EXPECT_EQ(table.rows.size(), 4u);
    EXPECT_EQ(table.replicates, 2u);
    EXPECT_EQ(provenance["replicates_left_out"], 2);
    // The same through the CSV route (campaign export, then surrogate fit --table).
    ex::exportCampaignCsv(spec.place, dir / "rep.csv");
    const auto csv = mixload::surrogates::readTable(dir / "rep.csv");
    EXPECT_EQ(csv.rows.size(), 4u);
    EXPECT_EQ(csv.replicates, 2u);
    // An extension continues the Sobol sequence after the design's own 6 points, not after the 8
    // rows the replicates make: the points a design of 8 would have had.
    ex::extendCampaign(spec.place, 2, false);
    ex::CampaignSpec eight = spec;
    eight.place = {"eight", dir.string()};
    eight.n = 8;
    ex::createCampaign(eight);
    const auto paramsAt = [](const std::string& name, const fs::path& ledger, int index) {
        for (const auto& r : Ledger(ledger).runs(name))
            if (r.index == index) return r.params;
        return nlohmann::json();
    };
    for (int k = 0; k < 2; ++k)
        for (const char* p : {"rpm", "feed_kg_h"})
            EXPECT_DOUBLE_EQ(paramsAt("rep", spec.place.ledger(), 8 + k)[p].get<double>(),
                             paramsAt("eight", eight.place.ledger(), 6 + k)[p].get<double>()) << p;
    fs::remove_all(dir);
}

// Adaptive picks go to the box's faces, where a variance is largest; --inset keeps them off the
// margin by which a design's box was widened beyond the user's (v2's first batch landed there). The
// results are written by hand: a loading that falls with speed and rises with feed.
TEST(Ledger, AdaptivePicksKeepTheirInsetFromTheBoxFaces) {
    namespace ex = mixload::experiments;
    const fs::path dir = fs::temp_directory_path() / ("mixload-inset-" + std::to_string(::getpid()));
    const auto spec = sobolMixerCampaign("inset", dir, 6, kRpmFeedRanges);
    {
        Ledger l(spec.place.ledger());
        while (auto r = l.claimNext("inset", 2, false)) {
            const double m = 0.05 * r->params["feed_kg_h"].get<double>() / r->params["rpm"].get<double>() * 39;
            l.markDone(r->id, {{"loading_kg", m}, {"steady", true}}, 1, 1, "/x");
        }
    }
    // How far a pick lies from the nearest face, as a share of its range's width.
    const auto faceDistance = [](const nlohmann::json& params) {
        const double u = (params["rpm"].get<double>() - 39) / 215, v = (params["feed_kg_h"].get<double>() - 5) / 40;
        return std::min({u, 1 - u, v, 1 - v});
    };
    EXPECT_THROW(ex::extendCampaign(spec.place, 2, true, ex::AdaptiveCriterion::Variance, 0.3), mixload::InputError);
    const auto plain = ex::extendCampaign(spec.place, 3, true);
    double nearest = 1;
    for (const auto& p : plain["adaptive"]["picks"]) nearest = std::min(nearest, faceDistance(p["params"]));
    EXPECT_LT(nearest, 0.02) << "without an inset the variance should pick a face";
    const auto inset = ex::extendCampaign(spec.place, 3, true, ex::AdaptiveCriterion::Variance, 0.1);
    ASSERT_EQ(inset["adaptive"]["picks"].size(), 3u);
    EXPECT_EQ(inset["adaptive"]["inset"], 0.1);
    for (const auto& p : inset["adaptive"]["picks"]) EXPECT_GE(faceDistance(p["params"]), 0.1 - 1e-12) << p.dump();
    fs::remove_all(dir);
}

// A replicate that settles in another steady state (v2's 250 rpm point: a 0.110 kg bed, and from a
// smaller deposit a 0.016 kg film) is not the steady test's scatter: the pair is flagged and kept
// out of the noise, which the other pair alone gives.
TEST(Ledger, AReplicateInAnotherSteadyStateIsNotCountedAsNoise) {
    namespace ex = mixload::experiments;
    const fs::path dir = fs::temp_directory_path() / ("mixload-two-states-" + std::to_string(::getpid()));
    const auto spec = sobolMixerCampaign("two", dir, 4, "scene = \"mixer\"\n[rpm]\nmin = 39\nmax = 254\nunit = \"rpm\"\n");
    Ledger l(spec.place.ledger());
    std::map<std::string, double> loading;
    while (auto r = l.claimNext("two", 2, false)) {
        loading[r->params["rpm"].dump()] = 0.1 * (r->index + 1);
        l.markDone(r->id, {{"loading_kg", 0.1 * (r->index + 1)}, {"steady", true}}, 1, 1, "/x");
    }
    ASSERT_EQ(ex::replicateCampaign(spec.place, 2, 0.5)["added"], 2);
    double factor = 1.03;  // the first replicate: scatter; the second: a film 6.8x below its bed
    while (auto r = l.claimNext("two", 2, false)) {
        l.markDone(r->id, {{"loading_kg", factor * loading.at(r->params["rpm"].dump())}, {"steady", true}}, 1, 1, "/x");
        factor = 1 / 6.8;
    }
    const auto noise = ex::campaignNoise(spec.place);
    ASSERT_EQ(noise["pairs"].size(), 2u);
    EXPECT_EQ(noise["n"], 1);
    EXPECT_EQ(noise["two_state_pairs"], 1);
    EXPECT_EQ(noise["pairs"][0]["two_states"].get<bool>() + noise["pairs"][1]["two_states"].get<bool>(), 1);
    EXPECT_NEAR(noise["run_noise"].get<double>(), 0.03 / 1.015 / std::sqrt(2.0), 1e-9);
    fs::remove_all(dir);
}

TEST(Ledger, FidelityPilotPairsTwoCampaignsPointByPoint) {
    // The same design on two meshes (campaign create with the same ranges, n and seed): the pilot
    // pairs the points steady in both whose inputs agree. The results are written by hand: this
    // checks the pairing and the fit, not the solver.
    namespace ex = mixload::experiments;
    const fs::path dir = fs::temp_directory_path() / ("mixload-fidelity-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const auto make = [&](const std::string& name, double scale, int unsteady) {
        Ledger l(dir / name / "ledger.sqlite");
        auto c = info(name);
        l.createCampaign(c, points(10));
        while (auto r = l.claimNext(name, 2, false)) {
            const double m = 0.05 * (r->index + 1);
            l.markDone(r->id, {{"loading_kg", scale * m}, {"steady", r->index != unsteady}}, 1, 1, "/x");
        }
    };
    make("fine", 1.0, 3);
    make("coarse", 0.8, 7);
    // A point whose inputs differ is not a pair, though its index matches.
    {
        Ledger l(dir / "other" / "ledger.sqlite");
        l.createCampaign(info("other"), {{{"aspect", 99.0}}});
        const auto r = l.claimNext("other", 2, false);
        l.markDone(r->id, {{"loading_kg", 1.0}, {"steady", true}}, 1, 1, "/x");
    }
    const auto j = ex::fidelityPilot(dir / "fine", dir / "coarse", dir / "out");
    EXPECT_EQ(j["pairs"], 8);  // 10 points, one unsteady on each side
    EXPECT_NEAR(j["fit"]["slope"].get<double>(), 1.25, 1e-12);
    EXPECT_NEAR(j["fit"]["r2"].get<double>(), 1.0, 1e-12);
    EXPECT_NEAR(j["log_fit"]["residual_scatter"].get<double>(), 0.0, 1e-9);  // a constant ratio
    EXPECT_EQ(j["verdict"].get<std::string>().rfind("earns its place", 0), 0u) << j["verdict"];
    // A coarse mesh that is right on the large loadings and 2.5 times too light on the small ones:
    // r^2 on M stays high, the log-space scatter does not, and co-kriging is not worth it.
    {
        Ledger l(dir / "thin" / "ledger.sqlite");
        l.createCampaign(info("thin"), points(10));
        while (auto r = l.claimNext("thin", 2, false)) {
            const double m = 0.05 * (r->index + 1);
            l.markDone(r->id, {{"loading_kg", r->index < 3 ? 0.4 * m : m}, {"steady", true}}, 1, 1, "/x");
        }
    }
    const auto thin = ex::fidelityPilot(dir / "fine", dir / "thin", dir / "out4");
    EXPECT_GT(thin["fit"]["r2"].get<double>(), 0.9);
    EXPECT_GT(thin["log_fit"]["residual_scatter"].get<double>(), 0.1);
    EXPECT_EQ(thin["verdict"].get<std::string>().rfind("skip", 0), 0u) << thin["verdict"];
    EXPECT_EQ(ex::fidelityPilot(dir / "fine", dir / "other", dir / "out2")["pairs"], 0);
    EXPECT_THROW(ex::fidelityPilot(dir / "fine", dir / "none", dir / "out3"), mixload::InputError);
    fs::remove_all(dir);
}

TEST(Ledger, WarmStartTakesTheRunWhoseLoadingIsNearestTheModelsPrediction) {
    // Loadings written by hand that depend on the feed alone (M = feed/100). Point 7 (12.5 kg/h,
    // 106 rpm) lies nearest point 3 (20 kg/h, 120 rpm) in the unit cube but nearest point 2
    // (15 kg/h, 200 rpm) in loading: with four finished runs the start is the unit-cube neighbour,
    // with six the model's prediction picks point 2.
    namespace ex = mixload::experiments;
    const fs::path dir = fs::temp_directory_path() / ("mixload-warm-" + std::to_string(::getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    const fs::path ranges = dir / "r.toml";
    mixload::writeFileAtomic(ranges, "scene = \"mixer\"\n[rpm]\nmin = 39\nmax = 254\nunit = \"rpm\"\n[feed_kg_h]\nmin = 5\nmax = 45\nunit = \"kg/h\"\n");
    ex::CampaignSpec spec;
    spec.place = {"warm", dir.string()};
    spec.ranges = ranges.string();
    spec.design = "sobol";
    spec.n = 8;
    spec.scene = "gcm250-v3";
    ex::createCampaign(spec);
    EXPECT_TRUE(ex::campaignWarmSource(spec.place, 7).empty());  // nothing finished: the deposit
    const auto finish = [&](int upTo) {
        Ledger l(spec.place.ledger());
        for (const auto& r : l.runs("warm")) {
            if (r.index >= upTo || r.status == "done") continue;
            const auto c = l.claimNext("warm", 2, false);
            ASSERT_TRUE(c);
            ASSERT_EQ(c->index, r.index);
            const fs::path run = dir / ("run" + std::to_string(c->index));
            fs::create_directories(run);
            mixload::writeFileAtomic(run / "result.json", "{}");
            l.markDone(c->id, {{"loading_kg", c->params["feed_kg_h"].get<double>() / 100}, {"steady", true}}, 1, 1, run.string());
        }
    };
    finish(4);
    EXPECT_EQ(ex::campaignWarmSource(spec.place, 7).filename(), "run3");
    finish(6);
    EXPECT_EQ(ex::campaignWarmSource(spec.place, 7).filename(), "run2");
    // Replicates are no starts: one from another deposit may sit in another steady state. Each of
    // the six is replicated and finishes at its point's loading; with run 2 gone from the machine,
    // its replicate (same place, same loading) would be the start if replicates counted.
    ex::replicateCampaign(spec.place, 6, 0.5);
    {
        Ledger l(spec.place.ledger());
        std::vector<long> design;
        while (const auto c = l.claimNext("warm", 2, false)) {
            if (!mixload::store::isReplicate(*c)) {
                design.push_back(c->id);
                continue;
            }
            const fs::path run = dir / ("rep" + std::to_string(c->index));
            fs::create_directories(run);
            mixload::writeFileAtomic(run / "result.json", "{}");
            l.markDone(c->id, {{"loading_kg", c->params["feed_kg_h"].get<double>() / 100}, {"steady", true}}, 1, 1, run.string());
        }
        for (const long id : design) l.release(id);
        EXPECT_EQ(design.size(), 2u);
    }
    fs::remove(dir / "run2" / "result.json");
    const auto start = ex::campaignWarmSource(spec.place, 7).filename().string();
    EXPECT_EQ(start.rfind("run", 0), 0u) << start;
    EXPECT_NE(start, "run2");
    mixload::writeFileAtomic(dir / "run2" / "result.json", "{}");
    EXPECT_THROW(ex::campaignWarmSource(spec.place, 99), mixload::InputError);
    // A hold-out campaign with nothing finished of its own starts from the training campaign's runs
    // (--warm-from-campaign): each point takes the training run whose loading is nearest the
    // model's prediction there.
    ex::CampaignSpec hold = spec;
    hold.place.name = "hold";
    hold.design = "lhs";
    hold.n = 3;
    ex::createCampaign(hold);
    {
        mixload::store::Ledger l(hold.place.ledger());
        const auto runs = l.runs("hold");
        EXPECT_TRUE(ex::campaignWarmSource(hold.place, runs[0].index).empty());  // no pool: the deposit
        mixload::store::Ledger train(spec.place.ledger());
        const auto trainRuns = train.runs("warm");
        for (const auto& r : runs) {
            const auto w = ex::campaignWarmSource(hold.place, r.index, {spec.place});
            ASSERT_FALSE(w.empty());
            EXPECT_EQ(w.parent_path(), dir) << w;  // one of the training campaign's run directories
            // The model sees M = feed/100 exactly: the start is the finished run nearest in feed.
            const double feed = r.params["feed_kg_h"].get<double>();
            std::string nearest;
            double best = 1e300;
            for (const auto& t : trainRuns) {
                if (t.status != "done") continue;
                const double d = std::abs(std::log(t.params["feed_kg_h"].get<double>() / feed));
                if (d < best) best = d, nearest = "run" + std::to_string(t.index);
            }
            EXPECT_EQ(w.filename(), nearest) << "hold point at " << feed << " kg/h";
        }
    }
    // A pool on another base (another mesh) is refused: its fields would not fit the run's mesh.
    ex::CampaignSpec other = spec;
    other.place.name = "other";
    other.cellSize = 0.0075;
    ex::createCampaign(other);
    EXPECT_THROW(ex::campaignWarmSource(hold.place, 0, {other.place}), mixload::InputError);
    // So is one on the same base that varies other inputs: its runs have no place in this design.
    const fs::path rpmOnly = dir / "rpm.toml";
    mixload::writeFileAtomic(rpmOnly, "scene = \"mixer\"\n[rpm]\nmin = 39\nmax = 254\nunit = \"rpm\"\n");
    ex::CampaignSpec speed = spec;
    speed.place.name = "speed";
    speed.ranges = rpmOnly.string();
    ex::createCampaign(speed);
    EXPECT_THROW(ex::campaignWarmSource(hold.place, 0, {speed.place}), mixload::InputError);
    fs::remove_all(dir);
}
