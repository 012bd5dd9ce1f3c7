// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace mixload::run {

// A solver or utility that failed; what() carries the tail of its log.
class RunError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Environment Debian's OpenFOAM binaries need, plus Open MPI's consent to run as root (CI is root).
std::vector<std::pair<std::string, std::string>> foamEnvironment();

// Runs an OpenFOAM utility in caseDir, logging to log.<name>; throws RunError on failure.
void runUtility(const std::filesystem::path& caseDir, const std::vector<std::string>& argv);

// mixload's own build of interFoam (fullcfd/solver; MIXLOAD_INTERFOAM overrides), not Debian's
// /usr/bin/interFoam, which diverges on meshes whose faces are not aligned with the axes.
std::string interFoamPath();

struct SolverRun {
    std::filesystem::path caseDir;
    std::string solver = interFoamPath();
    int np = 1;
    double endTime = 1.0;   // for progress only
    bool progress = false;  // show percentage/ETA on a terminal
    std::string label = "run";
    // Stop the solver here (DeadlineReached); the case resumes from its last written time.
    std::optional<std::chrono::steady_clock::time_point> deadline;
};

// Runs the solver to completion (serial, or decomposePar + mpirun + reconstructPar). Resumes from
// the latest written time when the case already ran. Returns wall seconds spent in this call.
double runSolver(const SolverRun& r);

// A latest time directory that a killed solver left half written (a file without OpenFOAM's
// closing divider, or a file the time before it has and it lacks) is renamed to "<time>.partial",
// which OpenFOAM ignores, so that the solver resumes from the last complete time. Returns the new
// name, or nothing when the latest time is complete. runSolver does it before a serial run.
std::optional<std::filesystem::path> setAsidePartialTime(const std::filesystem::path& caseDir);

// A parallel case's times in processor*/ (a slice stopped at its deadline, or killed, did not
// reconstruct them): times past the latest one every rank wrote whole are set aside on every rank,
// newer ones are reconstructed into the case, and the decomposition is removed when the run resumes
// on another number of ranks (np) than it has.
void gatherParallelTimes(const std::filesystem::path& caseDir, int np);

// A solver that wrote its times with more digits than the case's timePrecision (OpenFOAM adds
// digits when write times drift apart) must restart with a precision that names its latest time as
// written: v1912's own search for more digits stops early (at 74.68951163209499 its 18- and
// 17-digit names agree, so it never tries 16 and looks for 74.68951163), and never tries fewer.
// Sets timePrecision in system/controlDict to the least precision that names the latest time of
// the case (decomposed: of each processor*/) as written, when the one it has does not; returns the
// precision the case then has (0 without one). runSolver does it before starting the solver.
int fitTimePrecision(const std::filesystem::path& caseDir, bool decomposed = false);

// Latest time directory (numeric name, as written: a restart needs its digits) of a case, or an
// empty path if none past 0; latestTime is its time, or 0.
std::filesystem::path latestTimeDir(const std::filesystem::path& caseDir);
double latestTime(const std::filesystem::path& caseDir);

}  // namespace mixload::run
