// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <optional>
#include <thread>

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
