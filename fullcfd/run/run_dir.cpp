// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/run_dir.hpp"

#include <chrono>
#include <optional>
#include <iostream>

#include "cases/foam_numerics.hpp"
#include "common/atomic_file.hpp"
#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "mixload_version.hpp"
#include "post/snapshots.hpp"
#include "run/foam_runner.hpp"

namespace mixload::run {

namespace fs = std::filesystem;

namespace {
fs::path lockFile(fs::path dir) { return dir += ".lock"; }
}  // namespace

RunDirLock::RunDirLock(const fs::path& dir)
    : lock_(lockFile(dir), FileLock::Mode::wait, [&] {
          std::cerr << "mixload: waiting for another mixload process that is running " << dir.string() << '\n';
      }) {}

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

void recordRunCost(nlohmann::json& result, const CountedSolve& cost, std::chrono::steady_clock::time_point t0,
                   int np, bool resumed) {
    result["wall_seconds"] = cost.total["wall_seconds"];
    result["core_seconds"] = cost.total["core_seconds"];
    result["slices"] = cost.total["slices"];
    result["slice_wall_seconds"] = secondsSince(t0);
    result["solver_wall_seconds"] = cost.solverWall;
    result["np"] = np;
    result["resumed"] = resumed;
}

void finishRun(nlohmann::json& result, const fs::path& dir, const std::string& hash, const fs::path& plot,
               const std::string& plotWarning, bool snapshots) {
    result["run_dir"] = dir.string();
    result["scene_hash"] = hash;
    result["mixload_version"] = kVersion;
    result["git_commit"] = kGitCommit;
    result["openfoam_version"] = MIXLOAD_OPENFOAM_VERSION;
    result["plot"] = plotWarning.empty() ? plot.string() : "";
    if (!plotWarning.empty()) result["plot_warning"] = plotWarning;
    writeFileAtomic(dir / "result.json", result.dump(2));
    if (snapshots) addSnapshots(result, dir);
}

namespace {
// Seconds on the clock the file system stamps files with, so that a slice's start and its logs'
// last writes compare directly.
double fileClockNow() {
    return std::chrono::duration<double>(fs::file_time_type::clock::now().time_since_epoch()).count();
}

// When anything in the case last wrote a log: the end of a slice whose process was killed.
std::optional<double> lastLogWrite(const fs::path& dir) {
    std::optional<double> last;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().filename().string().rfind("log.", 0) != 0) continue;
        const double t = fileClockOf(e.path());
        last = std::max(last.value_or(t), t);
    }
    return last;
}
}  // namespace

// (The file clock's epoch may lie in the future: its readings can be negative.)
double fileClockOf(const fs::path& p) {
    return std::chrono::duration<double>(fs::last_write_time(p).time_since_epoch()).count();
}

nlohmann::json closedSlices(const fs::path& dir, std::optional<double> end, const std::string& why) {
    const fs::path file = dir / "slices.json";
    auto slices = fs::exists(file) ? nlohmann::json::parse(readFile(file)) : nlohmann::json::array();
    for (auto& s : slices)
        if (s.value("open", false)) {
            const double start = s.at("start_file_clock_s").get<double>();
            const double wall = std::max(0.0, end.value_or(start) - start);
            s = {{"start_file_clock_s", s["start_file_clock_s"]}, {"wall_seconds", wall}, {"core_seconds", wall * s.value("np", 1)},
                 {"closed_by", why}};
        }
    return slices;
}

RunSlices::RunSlices(const fs::path& dir, int np) : file_(dir / "slices.json") {
    slices_ = closedSlices(dir, lastLogWrite(dir), "the next process (this one was killed): ended at its last log write");
    slices_.push_back({{"start_file_clock_s", fileClockNow()}, {"np", np}, {"open", true}});
    writeFileAtomic(file_, slices_.dump(1));
}

nlohmann::json RunSlices::close(double wallSeconds, double coreSeconds) {
    auto& s = slices_.back();
    s = {{"start_file_clock_s", s["start_file_clock_s"]}, {"wall_seconds", wallSeconds}, {"core_seconds", coreSeconds}};
    writeFileAtomic(file_, slices_.dump(1));
    double wall = 0, core = 0;
    for (const auto& x : slices_) wall += x.value("wall_seconds", 0.0), core += x.value("core_seconds", 0.0);
    return {{"wall_seconds", wall}, {"core_seconds", core}, {"slices", slices_.size()}};
}

CountedSolve runSolverCounted(const SolverRun& r, std::chrono::steady_clock::time_point t0, double meshSeconds) {
    cases::refreshFoamLibs(r.caseDir);
    RunSlices slices(r.caseDir, r.np);
    const auto tSolver = std::chrono::steady_clock::now();
    CountedSolve out;
    try {
        out.solverWall = runSolver(r);
    } catch (...) {
        // Stopped at a deadline, or failed: the next process resumes here and counts this time.
        slices.close(secondsSince(t0), meshSeconds + secondsSince(tSolver) * r.np);
        throw;
    }
    out.total = slices.close(secondsSince(t0), meshSeconds + out.solverWall * r.np);
    return out;
}

}  // namespace mixload::run
