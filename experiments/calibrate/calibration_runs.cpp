// SPDX-License-Identifier: GPL-3.0-or-later
#include "calibrate/calibration_runs.hpp"

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "common/process.hpp"
#include "mixload_version.hpp"
#include "run/foam_runner.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

CalibrationRuns::CalibrationRuns(const fs::path& dir, const std::string& name, const std::string& command,
                                 store::CampaignInfo info, const nlohmann::json& spec, double maxHours)
    : name_(name), home_(dir / name), lock_(home_, command), ledger_(home_ / "ledger.sqlite") {
    if (const auto stored = ledger_.campaign(name)) {
        if (stored->design != "calibration" || nlohmann::json::parse(stored->rangesToml) != spec)
            throw InputError("name", name,
                             "a new name, or the same parameters, targets and base scene: " + ledgerFile().string() +
                                 " holds another calibration");
    } else {
        info.name = name;
        info.design = "calibration";
        info.rangesToml = spec.dump();
        info.mixloadVersion = kVersion;
        info.gitCommit = kGitCommit;
        ledger_.createCampaign(info, {});
    }
    // A driver killed mid-run left its row running: take it up again (its run directory resumes
    // from its last written time).
    ledger_.requeueRunning(name);
    deadline_ = deadlineAfterHours(maxHours);
}

std::optional<store::LedgerRun> CalibrationRuns::row(const std::string& hash) const {
    std::optional<store::LedgerRun> found;
    for (auto& r : ledger_.runs(name_))
        if (r.params.value("scene_hash", "") == hash) found = r;
    return found;
}

std::optional<nlohmann::json> CalibrationRuns::finished(const std::string& hash, const std::string& label) {
    const auto r = row(hash);
    if (r && r->status == "failed")
        throw run::RunError("calibration " + name_ + ": the run at " + label + " failed twice (" + r->error +
                            "); see " + r->runDir);
    if (!r || r->status != "done") return std::nullopt;
    ++reused_;
    nlohmann::json q = r->result;
    q["run_dir"] = r->runDir;
    q["reused"] = true;
    return q;
}

store::LedgerRun CalibrationRuns::claim(const std::string& hash, const nlohmann::json& point) {
    auto r = row(hash);
    if (!r) {
        nlohmann::json p = point;
        p["scene_hash"] = hash;
        ledger_.addPoints(name_, {p});
        r = row(hash);
    }
    // This run and no other: a queued row may be one an earlier fit asked for and this one does not
    // (a fit whose algorithm changed); it stays queued, harmless.
    const auto claimed = ledger_.claimNext(name_, 2, false, r->id);
    if (!claimed)
        throw std::runtime_error("calibration " + name_ + ": run " + hash +
                                 " is taken (another driver on the same calibration?)");
    return *claimed;
}

fs::path CalibrationRuns::runDir(const store::LedgerRun& claimed, const std::string& hash) const {
    return home_ / "runs" / (std::to_string(claimed.index) + "-" + hash);
}

nlohmann::json CalibrationRuns::done(const store::LedgerRun& claimed, const std::string& kind,
                                     const nlohmann::json& result, const fs::path& dir, int np) {
    nlohmann::json q = store::runQois(kind, result);
    const double wall = result.value("wall_seconds", 0.0);
    ledger_.markDone(claimed.id, q, wall, result.value("core_seconds", wall * np), dir.string());
    ++newRuns_;
    q["run_dir"] = dir.string();
    q["reused"] = false;
    return q;
}

void CalibrationRuns::stopped(const store::LedgerRun& claimed) { ledger_.release(claimed.id); }

void CalibrationRuns::failed(const store::LedgerRun& claimed, const std::string& error) {
    ledger_.markFailed(claimed.id, error, claimed.attempts >= 2);
}

nlohmann::json CalibrationRuns::get(const std::string& hash, const nlohmann::json& point, const std::string& label,
                                    const std::string& kind, int np,
                                    const std::function<nlohmann::json(const fs::path&)>& run) {
    if (auto q = finished(hash, label)) return *q;
    const store::LedgerRun claimed = claim(hash, point);
    const fs::path dir = runDir(claimed, hash);
    try {
        return done(claimed, kind, run(dir), dir, np);
    } catch (const DeadlineReached&) {
        stopped(claimed);
        throw;
    } catch (const std::exception& e) {
        failed(claimed, e.what());
        throw;
    }
}

FitOutcome runFit(const std::string& name, const std::vector<CalibrationBound>& bounds, const ResidualFn& residuals,
                  const CalibrationOptions& opt, bool progressLine,
                  const std::function<void(const CalibrationTrace&)>& progress) {
    FitOutcome out;
    const auto onEval = [&](const CalibrationTrace& t) {
        out.trace = t;
        progress(t);
        if (progressLine)
            std::cerr << "calibration " << name << ": evaluation " << t.x.size() - 1 << " rms residual "
                      << formatNumber(t.rms.back()) << '\n';
    };
    try {
        out.trace = calibrate(bounds, residuals, opt, onEval);
    } catch (const DeadlineReached&) {
        out.trace.stop = "max-hours";
        out.stopped = true;
    }
    return out;
}

void requireCalibrationName(const std::string& name) {
    if (name.empty() || name.find_first_of("/\\ ") != std::string::npos)
        throw InputError("name", name, "a non-empty name without '/', '\\' or blanks");
}

double roundSignificant(double v, int digits) {
    char b[32];
    std::snprintf(b, sizeof b, "%.*g", digits, v);
    return std::strtod(b, nullptr);
}

std::string sig4(double v) {
    std::ostringstream os;
    os.precision(4);
    os << v;
    return os.str();
}

}  // namespace mixload::experiments
