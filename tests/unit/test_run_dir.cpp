// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <optional>
#include <thread>

#include "campaign/driver_lock.hpp"
#include "common/atomic_file.hpp"
#include "common/process.hpp"
#include "run/collapse_job.hpp"
#include "run/foam_runner.hpp"
#include "run/mixer_job.hpp"
#include "run/run_dir.hpp"
#include "scene/collapse_scene.hpp"
#include "scene/mixer_scene.hpp"

using namespace mixload;
namespace fs = std::filesystem;

// Two holders of the same run directory must not overlap: the second one waits until the first
// lets go. flock locks belong to the open file, so a second lock in the same process conflicts
// just as one in another process would.
TEST(RunDirLock, SecondHolderWaitsForTheFirst) {
    const fs::path dir = fs::temp_directory_path() / "mixload-lock-test" / "run";
    fs::remove_all(dir.parent_path());
    std::optional<run::RunDirLock> first(std::in_place, dir);
    std::atomic<bool> second{false};
    std::thread t([&] {
        const run::RunDirLock lock(dir);
        second = true;
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_FALSE(second) << "the second lock was granted while the first was held";
    first.reset();
    t.join();
    EXPECT_TRUE(second);
    // The lock creates only the parent and leaves nothing behind once released.
    EXPECT_FALSE(fs::exists(dir));
    EXPECT_TRUE(fs::exists(dir.parent_path()));
    EXPECT_FALSE(fs::exists(dir.parent_path() / "run.lock"));
    fs::remove_all(dir.parent_path());
}

// A second driver on the same ledger is refused at once (it would take up the first one's running
// rows), and the home is free again once the first lets go.
TEST(DriverLock, SecondDriverIsRefusedWhileTheFirstHolds) {
    const fs::path home = fs::temp_directory_path() / "mixload-driver-lock-test" / "cal";
    fs::remove_all(home.parent_path());
    std::optional<experiments::DriverLock> first(std::in_place, home, "calibrate mixer --name cal");
    try {
        const experiments::DriverLock second(home, "calibrate mixer --name cal");
        ADD_FAILURE() << "the second driver was let in";
    } catch (const run::RunError& e) {
        EXPECT_NE(std::string(e.what()).find("another `mixload calibrate mixer --name cal` is driving"),
                  std::string::npos)
            << e.what();
    }
    first.reset();
    EXPECT_NO_THROW(experiments::DriverLock(home, "calibrate mixer --name cal"));
    EXPECT_FALSE(fs::exists(home / "driver.lock"));
    fs::remove_all(home.parent_path());
}

// Past its deadline a job begins nothing (no case, no mesh: NotStarted, which drivers treat as a
// stop), yet a run that finished earlier is still returned: a late driver reports it, not "stopped".
TEST(RunDeadline, PastTheDeadlineNothingStartsAndFinishedRunsAreRead) {
    const fs::path root = fs::temp_directory_path() / "mixload-deadline-test";
    fs::remove_all(root);
    const auto past = std::chrono::steady_clock::now() - std::chrono::seconds(1);

    run::MixerJob mixer;
    mixer.scene = scene::loadMixerScene(scene::kDefaultMixerScene);
    mixer.out = root / "mixer";
    mixer.deadline = past;
    EXPECT_THROW(run::runMixer(mixer), NotStarted);
    EXPECT_FALSE(fs::exists(mixer.out));
    EXPECT_FALSE(fs::exists(root / "mixer.tmp"));

    scene::CollapseScene c;
    c.material = scene::loadMaterial("quartz");
    run::CollapseJob collapse;
    collapse.scene = c;
    collapse.out = root / "collapse";
    collapse.deadline = past;
    EXPECT_THROW(run::runCollapse(collapse), NotStarted);
    EXPECT_FALSE(fs::exists(collapse.out));

    // A finished run directory (its scene and result written) is read however late it is asked.
    fs::create_directories(mixer.out);
    writeFileAtomic(mixer.out / "scene.json", nlohmann::json{{"hash", mixer.scene.hash()}}.dump());
    writeFileAtomic(mixer.out / "result.json", nlohmann::json{{"loading_kg", 0.25}}.dump());
    const auto done = run::runMixer(mixer);
    EXPECT_EQ(done.value("loading_kg", 0.0), 0.25);
    EXPECT_TRUE(done.value("reused", false));
    fs::remove_all(root);
}
