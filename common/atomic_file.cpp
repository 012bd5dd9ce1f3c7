// SPDX-License-Identifier: GPL-3.0-or-later
#include "common/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace mixload {

std::filesystem::path atomicTempPath(const std::filesystem::path& path) {
    // A per-process counter keeps two threads writing the same file apart.
    static std::atomic<unsigned> serial{0};
    auto tmp = path;
    tmp += ".tmp." + std::to_string(::getpid()) + "." + std::to_string(serial++);
    return tmp;
}

namespace {

[[noreturn]] void failOn(const std::filesystem::path& tmp, const std::string& what) {
    const int err = errno;
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw std::runtime_error(what + " " + tmp.string() + ": " + std::strerror(err));
}

void syncPath(const std::filesystem::path& p, int flags) {
    if (const int fd = ::open(p.c_str(), flags | O_CLOEXEC); fd >= 0) {
        const int rc = ::fsync(fd);
        ::close(fd);
        if (rc != 0) failOn(p, "cannot sync");
    }
}

}  // namespace

void commitAtomic(const std::filesystem::path& tmp, const std::filesystem::path& path) {
    // On disk before the rename, and the rename itself after it: a crash or power loss leaves the
    // old file or the new one, never an empty one under the final name.
    syncPath(tmp, O_RDONLY);
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        errno = ec.value();
        failOn(tmp, "cannot rename to " + path.string() + ":");
    }
    const auto dir = path.parent_path().empty() ? std::filesystem::path(".") : path.parent_path();
    if (const int d = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC); d >= 0) {
        ::fsync(d);
        ::close(d);
    }
}

void writeFileAtomic(const std::filesystem::path& path, const std::string& text) {
    const auto tmp = atomicTempPath(path);
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) failOn(tmp, "cannot write");
    for (size_t done = 0; done < text.size();) {
        const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            ::close(fd);
            failOn(tmp, "write failed:");
        }
        done += static_cast<size_t>(n);
    }
    if (::close(fd) != 0) failOn(tmp, "cannot close");
    commitAtomic(tmp, path);
}

std::string readFile(const std::filesystem::path& path) {
    std::ifstream is(path, std::ios::binary);
    if (!is) throw std::runtime_error("cannot read " + path.string());
    std::ostringstream ss;
    ss << is.rdbuf();
    return ss.str();
}

}  // namespace mixload
