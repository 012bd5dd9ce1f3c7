// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <optional>
#include <thread>

#include "campaign/driver_lock.hpp"
#include "run/foam_runner.hpp"
#include "run/run_dir.hpp"

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
