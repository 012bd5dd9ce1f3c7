// SPDX-License-Identifier: GPL-3.0-or-later
// One driver per ledger: a second `campaign run` or `calibrate` on the same home would take up the
// first one's running rows as if their driver had died, and run them twice.
#pragma once
#include <filesystem>
#include <memory>
#include <string>

#include "common/file_lock.hpp"

namespace mixload::experiments {

class DriverLock {
public:
    // Throws run::RunError naming `command` when another process drives home.
    DriverLock(const std::filesystem::path& home, const std::string& command);

private:
    std::unique_ptr<FileLock> lock_;
};

}  // namespace mixload::experiments
