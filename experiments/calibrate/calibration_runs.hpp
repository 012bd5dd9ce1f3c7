// SPDX-License-Identifier: GPL-3.0-or-later
// The full runs of one calibration (mixer or collapse): a SQLite ledger in <dir>/<name>/, one row
// per run keyed by its scene hash, guarded by the driver lock. A fit is deterministic, so a driver
// that asks this store for its runs replays its path from the ledger after an interruption: done
// runs are returned, not repeated; a run left "running" by a killed driver is taken up again and
// resumes from its last written time.
#pragma once
#include <chrono>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "calibrate/calibrator.hpp"
#include "campaign/driver_lock.hpp"
#include "store/ledger.hpp"

namespace mixload::experiments {

class CalibrationRuns {
public:
    // info: the base scene's record (scene, hash, json, method, mesh); spec: everything that
    // defines the fit. A ledger holding another spec under this name is refused (InputError).
    CalibrationRuns(const std::filesystem::path& dir, const std::string& name, const std::string& command,
                    store::CampaignInfo info, const nlohmann::json& spec, double maxHours);

    // The QoIs of the finished run with this scene hash, or nothing. A run that failed for good
    // throws run::RunError naming `label`.
    std::optional<nlohmann::json> finished(const std::string& hash, const std::string& label);

    // Claims the run with this hash (adding its row with `point` if new) and returns its row, with
    // the directory it runs in: <dir>/<name>/runs/<index>-<hash>.
    store::LedgerRun claim(const std::string& hash, const nlohmann::json& point);
    std::filesystem::path runDir(const store::LedgerRun& claimed, const std::string& hash) const;

    // The outcome of a claimed run: QoIs (kind mixer | collapse) with run_dir and reused added.
    nlohmann::json done(const store::LedgerRun& claimed, const std::string& kind, const nlohmann::json& result,
                        const std::filesystem::path& dir, int np);
    void stopped(const store::LedgerRun& claimed);  // by the deadline: back in the queue, uncounted
    void failed(const store::LedgerRun& claimed, const std::string& error);

    // finished(), else claim, run, and record: the sequential path. run(dir, deadline) returns the
    // run's full result record; exceptions (DeadlineReached included) are recorded and rethrown.
    nlohmann::json get(const std::string& hash, const nlohmann::json& point, const std::string& label,
                       const std::string& kind, int np,
                       const std::function<nlohmann::json(const std::filesystem::path&)>& run);

    const std::optional<std::chrono::steady_clock::time_point>& deadline() const { return deadline_; }
    std::filesystem::path home() const { return home_; }
    std::filesystem::path ledgerFile() const { return home_ / "ledger.sqlite"; }
    int newRuns() const { return newRuns_; }
    int reusedRuns() const { return reused_; }

private:
    std::optional<store::LedgerRun> row(const std::string& hash) const;

    std::string name_;
    std::filesystem::path home_;
    DriverLock lock_;  // before the ledger: requeueRunning must not take a live driver's row
    store::Ledger ledger_;
    std::optional<std::chrono::steady_clock::time_point> deadline_;
    int newRuns_ = 0, reused_ = 0;
};

// calibrate() with `progress(trace)` after every evaluation (the drivers write their in-progress
// report there) and a progress line on stderr when asked. A run stopped by the deadline ends the
// fit: the trace so far comes back with stop = "max-hours" and stopped set.
struct FitOutcome {
    CalibrationTrace trace;
    bool stopped = false;
};
FitOutcome runFit(const std::string& name, const std::vector<CalibrationBound>& bounds, const ResidualFn& residuals,
                  const CalibrationOptions& opt, bool progressLine,
                  const std::function<void(const CalibrationTrace&)>& progress);

// A calibration's name is a directory under --dir: InputError unless it is one plain path segment.
void requireCalibrationName(const std::string& name);

// v as the nearest number with that many significant digits prints: a scene built from it, and its
// hash, do not depend on how the arithmetic before it rounded (0.14 + 0.025 against 0.14 + 0.25 * 0.1).
double roundSignificant(double v, int digits);
// Four significant digits: what a report reader compares.
std::string sig4(double v);

}  // namespace mixload::experiments
