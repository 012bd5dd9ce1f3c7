// SPDX-License-Identifier: GPL-3.0-or-later
#include "campaign/driver_lock.hpp"

#include "run/foam_runner.hpp"

namespace mixload::experiments {

DriverLock::DriverLock(const std::filesystem::path& home, const std::string& command)
    : lock_(home / "driver.lock", FileLock::Mode::tryOnce) {
    if (!lock_.held())
        throw run::RunError("another `mixload " + command + "` is driving " + home.string() +
                            " (it holds " + (home / "driver.lock").string() + ")");
}

}  // namespace mixload::experiments
