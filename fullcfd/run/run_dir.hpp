// SPDX-License-Identifier: GPL-3.0-or-later
// What every full run does with its directory: refuse one that belongs to another scene, reuse a
// finished result, build a new case atomically, stamp results with provenance.
#pragma once
#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "common/file_lock.hpp"

namespace mixload::run {

// Holds an exclusive lock on "<dir>.lock" for its lifetime, so two mixload processes that share a
// run store (two studies, or a study and a hand-started run) never run the same case at once: the
// second waits, then finds the finished result.
class RunDirLock {
public:
    explicit RunDirLock(const std::filesystem::path& dir);

private:
    FileLock lock_;
};

// Throws InputError if dir exists but holds another scene; returns the stored result (marked
// "reused") when reuse is allowed and the run finished.
std::optional<nlohmann::json> checkRunDir(const std::filesystem::path& dir, const std::string& hash,
                                          bool reuse);

// Builds the case in a sibling "<dir>.tmp" with build(tmp) and renames it to dir: a directory
// under the final name always holds a complete case. A failed OpenFOAM utility (RunError) leaves
// its partial case in "<dir>.failed" for its logs; any other failure leaves nothing.
void buildCaseAtomically(const std::filesystem::path& dir,
                         const std::function<void(const std::filesystem::path&)>& build);

// Exports <dir>/snapshots.h5 unless the result already names an existing one, and records its path
// under "snapshots" in result and in <dir>/result.json.
void addSnapshots(nlohmann::json& result, const std::filesystem::path& dir);

// The wall and core seconds spent on a run over every process that worked on it: a run stopped at
// a deadline, or killed, resumes in its directory in a later process. Each process opens a slice in
// <dir>/slices.json and closes it with its own seconds when it ends, finished, stopped or failed. A
// slice left open by a killed process is closed by the next one at the last change of the case's
// logs (when the killed solver last wrote), its core seconds as that wall time on its ranks.
class RunSlices {
public:
    RunSlices(const std::filesystem::path& dir, int np);
    // Closes this process's slice; returns the totals: wall_seconds, core_seconds, slices.
    nlohmann::json close(double wallSeconds, double coreSeconds);

private:
    std::filesystem::path file_;
    nlohmann::json slices_;
};

// When a file was last written, in the seconds slices.json counts in (the file system's clock).
double fileClockOf(const std::filesystem::path& p);

// <dir>/slices.json with any slice left open (a process stopped or killed) closed at `end` (file
// clock seconds; none: no time) and marked `why`; empty without the file.
nlohmann::json closedSlices(const std::filesystem::path& dir, std::optional<double> end, const std::string& why);

struct SolverRun;

// Runs the solver as this process's slice of the run (RunSlices), closed whether the solver
// finishes, stops at its deadline or fails. t0: when this process began on the run; meshSeconds:
// the serial meshing before the solver held its np cores. Returns the solver's wall seconds and the
// run's totals (RunSlices::close).
struct CountedSolve {
    double solverWall = 0;
    nlohmann::json total;
};
CountedSolve runSolverCounted(const SolverRun& r, std::chrono::steady_clock::time_point t0, double meshSeconds);

// Records the run's cost over every process that worked on it (cost.total) and this process's
// share: wall_seconds, core_seconds, slices, slice_wall_seconds, solver_wall_seconds, np, resumed.
void recordRunCost(nlohmann::json& result, const CountedSolve& cost, std::chrono::steady_clock::time_point t0,
                   int np, bool resumed);

// A finished run's last steps, the same for every scene: provenance (run_dir, scene_hash,
// mixload_version, git_commit, openfoam_version), the plot's path or why there is none,
// <dir>/result.json written atomically, then the snapshots if asked.
void finishRun(nlohmann::json& result, const std::filesystem::path& dir, const std::string& hash,
               const std::filesystem::path& plot, const std::string& plotWarning, bool snapshots);

}  // namespace mixload::run
