// SPDX-License-Identifier: GPL-3.0-or-later
// The one inter-process lock mixload uses: an exclusive flock on a file, held for the object's
// lifetime. Run directories wait on it (two studies sharing a run store); drivers try it once (two
// drivers on one campaign or calibration). The kernel drops the lock when its process dies, so a
// stale file never blocks anyone.
#pragma once
#include <filesystem>
#include <functional>

namespace mixload {

class FileLock {
public:
    enum class Mode { wait, tryOnce };
    // Mode::wait blocks until held, calling onBusy once first if another process holds it;
    // Mode::tryOnce returns at once, held() false when another process holds it. Throws
    // std::runtime_error when the file cannot be opened or locked.
    FileLock(std::filesystem::path file, Mode mode, const std::function<void()>& onBusy = {});
    ~FileLock();
    FileLock(const FileLock&) = delete;
    FileLock& operator=(const FileLock&) = delete;

    bool held() const { return fd_ >= 0; }

private:
    std::filesystem::path path_;
    int fd_ = -1;
};

}  // namespace mixload
