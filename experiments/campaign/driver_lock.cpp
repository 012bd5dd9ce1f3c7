// SPDX-License-Identifier: GPL-3.0-or-later
#include "campaign/driver_lock.hpp"

#include <chrono>
#include <memory>
#include <thread>

#include "run/foam_runner.hpp"

namespace mixload::experiments {

namespace {
// `campaign status` holds the lock for an instant to see whether a driver runs: a driver starting
// then tries again for a moment before it calls the campaign taken.
std::unique_ptr<FileLock> takeDriverLock(const std::filesystem::path& file) {
    for (int i = 0;; ++i) {
        auto lock = std::make_unique<FileLock>(file, FileLock::Mode::tryOnce);
        if (lock->held() || i == 20) return lock;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
}
}  // namespace

DriverLock::DriverLock(const std::filesystem::path& home, const std::string& command)
    : lock_(takeDriverLock(home / "driver.lock")) {
    if (!lock_->held())
        throw run::RunError("another `mixload " + command + "` is driving " + home.string() +
                            " (it holds " + (home / "driver.lock").string() + ")");
}

}  // namespace mixload::experiments
