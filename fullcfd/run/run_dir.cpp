// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/run_dir.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "mixload_version.hpp"
#include "post/snapshots.hpp"
#include "run/foam_runner.hpp"

namespace mixload::run {

namespace fs = std::filesystem;

RunDirLock::RunDirLock(const fs::path& dir) : path_(dir) {
    path_ += ".lock";
    fs::create_directories(dir.parent_path());
    bool told = false;
    // The holder unlinks the file when it lets go, so a waiter may end up holding a lock on a file
    // that no longer has a name; it then starts over on the current file.
    for (;;) {
        fd_ = ::open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd_ < 0) throw RunError("cannot open " + path_.string() + ": " + std::strerror(errno));
        if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
            if (!told)
                std::cerr << "mixload: waiting for another mixload process that is running "
                          << dir.string() << '\n';
            told = true;
            while (::flock(fd_, LOCK_EX) != 0)
                if (errno != EINTR) {
                    const std::string why = std::strerror(errno);
                    ::close(fd_);
                    throw RunError("cannot lock " + path_.string() + ": " + why);
                }
        }
        struct stat held {}, named {};
        if (::fstat(fd_, &held) == 0 && ::stat(path_.c_str(), &named) == 0 &&
            held.st_ino == named.st_ino && held.st_dev == named.st_dev)
            return;
        ::close(fd_);
    }
}

RunDirLock::~RunDirLock() {
    if (fd_ < 0) return;
    // Unlink before unlocking: nothing is left beside the run, and no newcomer can lock the old file.
    ::unlink(path_.c_str());
    ::close(fd_);
}

std::optional<nlohmann::json> checkRunDir(const fs::path& dir, const std::string& hash, bool reuse) {
    if (!fs::exists(dir)) return std::nullopt;
    const fs::path sceneFile = dir / "scene.json";
    if (!fs::exists(sceneFile) || nlohmann::json::parse(readFile(sceneFile)).value("hash", "") != hash)
        throw InputError("out", dir.string(), "a new directory or a run directory of the same scene");
    if (reuse && fs::exists(dir / "result.json")) {
        auto r = nlohmann::json::parse(readFile(dir / "result.json"));
        r["reused"] = true;
        return r;
    }
    return std::nullopt;
}

void buildCaseAtomically(const fs::path& dir, const std::function<void(const fs::path&)>& build) {
    fs::path tmp = dir;
    tmp += ".tmp";
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    try {
        build(tmp);
    } catch (const RunError& e) {
        // A utility failed: keep its logs under a name that cannot pass for a case, and point
        // the message there instead of at the vanished tmp directory.
        fs::path failed = dir;
        failed += ".failed";
        fs::remove_all(failed);
        fs::rename(tmp, failed);
        std::string msg = e.what();
        for (auto at = msg.find(tmp.string()); at != std::string::npos;
             at = msg.find(tmp.string(), at + failed.string().size()))
            msg.replace(at, tmp.string().size(), failed.string());
        throw RunError(msg);
    } catch (...) {
        fs::remove_all(tmp);
        throw;
    }
    fs::remove_all(dir);
    fs::rename(tmp, dir);
}

void addSnapshots(nlohmann::json& result, const fs::path& dir) {
    if (result.contains("snapshots") && fs::exists(result["snapshots"].get<std::string>())) return;
    post::SnapshotExport e;
    e.runDir = dir;
    result["snapshots"] = post::exportSnapshots(e)["file"];
    nlohmann::json stored = result;
    stored.erase("reused");
    writeFileAtomic(dir / "result.json", stored.dump(2));
}

void stampProvenance(nlohmann::json& result, const fs::path& dir, const std::string& hash) {
    result["run_dir"] = dir.string();
    result["scene_hash"] = hash;
    result["mixload_version"] = kVersion;
    result["git_commit"] = kGitCommit;
    result["openfoam_version"] = MIXLOAD_OPENFOAM_VERSION;
}

}  // namespace mixload::run
