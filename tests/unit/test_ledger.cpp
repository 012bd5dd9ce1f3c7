// SPDX-License-Identifier: GPL-3.0-or-later
// The SQLite run ledger: queue semantics, retries, extensions, and a writer killed with SIGKILL in
// the middle of its transactions.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <set>
#include <sys/wait.h>
#include <unistd.h>

#include "store/ledger.hpp"

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
