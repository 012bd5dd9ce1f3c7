// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/file_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace mixload {

namespace fs = std::filesystem;

FileLock::FileLock(fs::path file, Mode mode, const std::function<void()>& onBusy) : path_(std::move(file)) {
    fs::create_directories(path_.parent_path());
    bool told = false;
    // The holder unlinks the file when it lets go, so a waiter may end up holding a lock on a file
    // that no longer has a name; it then starts over on the current file.
    for (;;) {
        const int fd = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0) throw std::runtime_error("cannot open " + path_.string() + ": " + std::strerror(errno));
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
            if (mode == Mode::tryOnce) {
                ::close(fd);
                return;
            }
            if (!told && onBusy) onBusy();
            told = true;
            while (::flock(fd, LOCK_EX) != 0)
                if (errno != EINTR) {
                    const std::string why = std::strerror(errno);
                    ::close(fd);
                    throw std::runtime_error("cannot lock " + path_.string() + ": " + why);
                }
        }
        struct stat held {}, named {};
        if (::fstat(fd, &held) == 0 && ::stat(path_.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
            held.st_dev == named.st_dev) {
            fd_ = fd;
            return;
        }
        ::close(fd);
    }
}

FileLock::~FileLock() {
    if (fd_ < 0) return;
    // Unlink before unlocking: nothing is left behind, and no newcomer can lock the old file.
    ::unlink(path_.c_str());
    ::close(fd_);
}

}  // namespace mixload
