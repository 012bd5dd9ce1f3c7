// SPDX-License-Identifier: GPL-3.0-or-later
#include "calibrate/mixer_calibration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "campaign/driver_lock.hpp"
#include "store/ledger.hpp"
#include "common/atomic_file.hpp"
#include "common/clock.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "common/process.hpp"
#include "mixload_version.hpp"
#include "run/foam_runner.hpp"
#include "run/mixer_job.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

using store::CampaignInfo;
using store::Ledger;
using store::LedgerRun;
using store::runQois;

namespace {

std::vector<std::string> splitColons(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string part; std::getline(ss, part, ':');) out.push_back(part);
    return out;
}

double number(const std::string& field, const std::string& text, const std::string& whole) {
    const auto v = parseNumber(text);
    if (!v || !std::isfinite(*v)) throw InputError(field, whole, "numbers separated by ':'");
    return *v;
}

// v as the nearest number with that many significant digits prints: a scene built from it, and its
// hash, do not depend on how the arithmetic before it rounded (0.14 + 0.025 against 0.14 + 0.25 * 0.1).
double roundSignificant(double v, int digits) {
    char b[32];
    std::snprintf(b, sizeof b, "%.*g", digits, v);
    return std::strtod(b, nullptr);
}

double maxAbs(const std::vector<double>& v) {
    double m = 0;
    for (double x : v) m = std::max(m, std::abs(x));
    return m;
}

// The scene of one run: the base with these keys, at the target's operating point (InputError if
// the scene refuses it).
scene::MixerScene sceneAt(const MixerCalibration& c, const scene::SceneKeys& keys, const LoadingTarget& t) {
    scene::MixerScene s = c.sceneFor(keys);
    s.rpm = t.rpm;
    s.feedKgH = t.feedKgH;
    s.validate();
    return s;
}

// Four significant digits: what a report reader compares.
std::string sig4(double v) {
    std::ostringstream os;
    os.precision(4);
    os << v;
    return os.str();
}

std::string targetLabel(const LoadingTarget& t) {
    return formatNumber(t.rpm) + " rpm, " + formatNumber(t.feedKgH) + " kg/h";
}

nlohmann::json specOf(const MixerCalibration& c) {
    nlohmann::json params = nlohmann::json::array(), targets = nlohmann::json::array();
    for (const auto& p : c.params) params.push_back({{"key", p.key}, {"lo", p.lo}, {"hi", p.hi}, {"start", p.start}});
    for (const auto& t : c.targets)
        targets.push_back({{"rpm", t.rpm}, {"feed_kg_h", t.feedKgH}, {"loading_kg", t.loadingKg}, {"tol", t.tol}});
    return {{"params", params},
            {"targets", targets},
            {"base_scene_hash", c.sceneFor({}).hash()},
            {"allow_unsteady", c.allowUnsteady}};
}

// One evaluation: the fitted keys and, per target, the run's loading.
struct Evaluation {
    scene::SceneKeys keys;
    std::vector<nlohmann::json> runs;  // per target: loading_kg, steady, residual, run_dir, reused
};

class Driver {
public:
    explicit Driver(const MixerCalibration& c)
        : c_(c), home_(c.dir / c.name), lock_(home_, "calibrate mixer --name " + c.name), ledger_(home_ / "ledger.sqlite") {
        const nlohmann::json spec = specOf(c);
        if (const auto stored = ledger_.campaign(c.name)) {
            if (stored->design != "calibration" || nlohmann::json::parse(stored->rangesToml) != spec)
                throw InputError("name", c.name,
                                 "a new name, or the same parameters, targets and base scene: " +
                                     (home_ / "ledger.sqlite").string() + " holds another calibration");
        } else {
            CampaignInfo info;
            const auto base = c.sceneFor({});
            info.name = c.name;
            info.scene = "mixer";
            info.sceneHash = base.hash();
            info.sceneJson = base.toJson();
            info.design = "calibration";
            info.method = base.method;
            info.mesh = base.meshLabel();
            info.rangesToml = spec.dump();
            info.mixloadVersion = kVersion;
            info.gitCommit = kGitCommit;
            ledger_.createCampaign(info, {});
        }
        // A driver killed mid-run left its row running: take it up again (its run directory
        // resumes from its last written time).
        ledger_.requeueRunning(c.name);
        deadline_ = deadlineAfterHours(c.maxHours);
    }

    std::vector<double> residuals(const std::vector<double>& x) {
        Evaluation e;
        for (size_t i = 0; i < x.size(); ++i) e.keys[c_.params[i].key] = roundSignificant(x[i], 6);
        std::vector<double> r;
        for (size_t k = 0; k < c_.targets.size(); ++k) {
            const auto& t = c_.targets[k];
            scene::MixerScene s = sceneAt(c_, e.keys, t);
            if (c_.sizeDeposit) {
                std::vector<std::vector<double>> xs;
                std::vector<double> ms;
                for (const auto& prev : evals_) {
                    std::vector<double> px;
                    for (const auto& p : c_.params) px.push_back(prev.keys.at(p.key));
                    xs.push_back(px);
                    ms.push_back(prev.runs.at(k).at("loading_kg").get<double>());
                }
                if (const auto m = depositFor(xs, ms, x, c_.params)) {
                    // Within what the scene accepts: a deposit the barrel can hold.
                    const double cap = 0.9 * s.geometry.openVolume() * s.bulkDensity();
                    s.initialLoadingKg = std::min(*m, cap);
                    s.validate();
                }
            }
            nlohmann::json run = runOnce(s, e.keys, t);
            run["deposit_kg"] = s.initialLoadingKg;
            const double m = run.at("loading_kg").get<double>();
            if (!run.value("steady", false) && !c_.allowUnsteady)
                throw run::RunError("calibration " + c_.name + ": the run at " + targetLabel(t) +
                                    " reached its end time without a steady loading (M = " +
                                    formatNumber(m) + " kg, " + run.value("run_dir", std::string()) +
                                    "); raise --end-time, or pass --allow-unsteady");
            run["residual"] = (m - t.loadingKg) / (t.tol * t.loadingKg);
            r.push_back(run["residual"].get<double>());
            e.runs.push_back(run);
        }
        evals_.push_back(e);
        return r;
    }

    nlohmann::json report(const CalibrationTrace& t, const std::string& status) const {
        nlohmann::json evals = nlohmann::json::array();
        for (size_t i = 0; i < evals_.size(); ++i)
            evals.push_back({{"keys", evals_[i].keys}, {"runs", evals_[i].runs}, {"rms", t.rms.at(i)}});
        nlohmann::json j{{"calibration", c_.name},
                         {"status", status},
                         {"stop", t.stop},
                         {"evaluations", evals},
                         {"runs_new", newRuns_},
                         {"runs_reused", reused_},
                         {"ledger", (home_ / "ledger.sqlite").string()},
                         {"spec", specOf(c_)},
                         {"mixload_version", kVersion},
                         {"git_commit", kGitCommit}};
        if (!evals_.empty()) {
            j["best"] = evals[t.best];
            j["best_max_residual"] = maxAbs(t.r[t.best]);
        }
        return j;
    }

    void writeReport(const nlohmann::json& j) const;

private:
    nlohmann::json runOnce(const scene::MixerScene& s, const scene::SceneKeys& keys, const LoadingTarget& t) {
        const std::string hash = s.hash();
        const auto find = [&] {
            std::optional<LedgerRun> row;
            for (auto& r : ledger_.runs(c_.name))
                if (r.params.value("scene_hash", "") == hash) row = r;
            return row;
        };
        std::optional<LedgerRun> row = find();
        if (row && row->status == "done") {
            ++reused_;
            return withRunDir(row->result, row->runDir, true);
        }
        if (row && row->status == "failed")
            throw run::RunError("calibration " + c_.name + ": the run at " + targetLabel(t) + " failed twice (" +
                                row->error + "); see " + row->runDir);
        if (!row) {
            ledger_.addPoints(c_.name, {{{"keys", keys}, {"rpm", t.rpm}, {"feed_kg_h", t.feedKgH}, {"scene_hash", hash}}});
            row = find();
        }
        // This run and no other: a queued row may be one an earlier fit asked for and this one
        // does not (a fit whose algorithm changed); it stays queued, harmless.
        const auto claimed = ledger_.claimNext(c_.name, 2, false, row->id);
        if (!claimed)
            throw std::runtime_error("calibration " + c_.name + ": run " + hash +
                                     " is taken (another driver on the same calibration?)");
        run::MixerJob job;
        job.scene = s;
        job.np = c_.np;
        job.progress = c_.progress;
        job.deadline = deadline_;
        job.out = home_ / "runs" / (std::to_string(claimed->index) + "-" + hash);
        try {
            const nlohmann::json res = run::runMixer(job);
            ledger_.markDone(claimed->id, runQois("mixer", res), res.value("wall_seconds", 0.0),
                             res.value("core_seconds", res.value("wall_seconds", 0.0) * c_.np), job.out.string());
            ++newRuns_;
            return withRunDir(runQois("mixer", res), job.out.string(), false);
        } catch (const DeadlineReached&) {
            ledger_.release(claimed->id);
            throw;
        } catch (const std::exception& e) {
            ledger_.markFailed(claimed->id, e.what(), claimed->attempts >= 2);
            throw;
        }
    }

    static nlohmann::json withRunDir(nlohmann::json q, const std::string& dir, bool reused) {
        q["run_dir"] = dir;
        q["reused"] = reused;
        return q;
    }

    const MixerCalibration& c_;
    fs::path home_;
    DriverLock lock_;  // before the ledger: requeueRunning must not take a live driver's row
    Ledger ledger_;
    std::optional<std::chrono::steady_clock::time_point> deadline_;
    std::vector<Evaluation> evals_;
    int newRuns_ = 0, reused_ = 0;
};

void Driver::writeReport(const nlohmann::json& j) const {
    const fs::path dir = home_ / "report";
    fs::create_directories(dir);
    std::ostringstream csv, md;
    csv << "eval";
    for (const auto& p : c_.params) csv << ',' << p.key;
    for (size_t k = 0; k < c_.targets.size(); ++k) csv << ",loading_kg_" << k << ",steady_" << k << ",residual_" << k;
    csv << ",rms\n";
    md << "# Calibration " << c_.name << "\n\nstatus: **" << j["status"].get<std::string>() << "** (stop: "
       << j["stop"].get<std::string>() << "); " << j["runs_new"] << " new runs, " << j["runs_reused"]
       << " from the ledger; mixload " << kVersion << " (" << kGitCommit << ")\n\n";
    md << "Targets:\n";
    for (const auto& t : c_.targets)
        md << "- " << targetLabel(t) << ": " << formatNumber(t.loadingKg) << " kg +- " << formatNumber(100 * t.tol) << "%\n";
    md << "\n| eval |";
    for (const auto& p : c_.params) md << ' ' << p.key << " |";
    for (const auto& t : c_.targets) md << " M at " << targetLabel(t) << " [kg] | residual |";
    md << " rms |\n|---|";
    for (size_t i = 0; i < c_.params.size() + 2 * c_.targets.size() + 1; ++i) md << "---|";
    md << '\n';
    const auto& evals = j["evaluations"];
    for (size_t i = 0; i < evals.size(); ++i) {
        const auto& e = evals[i];
        csv << i;
        md << "| " << i << " |";
        for (const auto& p : c_.params) {
            csv << ',' << e["keys"][p.key].get<double>();
            md << ' ' << sig4(e["keys"][p.key].get<double>()) << " |";
        }
        for (size_t k = 0; k < e["runs"].size(); ++k) {
            const auto& r = e["runs"][k];
            csv << ',' << r["loading_kg"].get<double>() << ',' << (r.value("steady", false) ? 1 : 0) << ','
                << r["residual"].get<double>();
            md << ' ' << sig4(r["loading_kg"].get<double>()) << (r.value("steady", false) ? "" : " (not steady)")
               << (r.contains("deposit_kg") ? " from " + sig4(r["deposit_kg"].get<double>()) : std::string())
               << " | " << sig4(r["residual"].get<double>()) << " |";
        }
        csv << ',' << e["rms"].get<double>() << '\n';
        md << ' ' << sig4(e["rms"].get<double>()) << " |\n";
    }
    md << "\nResiduals are (M - target) / (tol x target): within the band when |residual| <= 1.\n";
    // M against each parameter, one point type per target, with the targets' bands.
    std::ostringstream data;
    for (size_t k = 0; k < c_.targets.size(); ++k) {
        for (const auto& e : evals) {
            for (const auto& p : c_.params) data << e["keys"][p.key].get<double>() << ' ';
            data << e["runs"][k]["loading_kg"].get<double>() << '\n';
        }
        data << "\n\n";
    }
    writeFileAtomic(dir / "calibration.dat", data.str());
    std::ostringstream gp;
    const size_t n = c_.params.size();
    gp << "set terminal pngcairo size " << 520 * n << ",420\nset output 'calibration.png'\n"
       << "set multiplot layout 1," << n << " title 'calibration " << c_.name << " (" << j["status"].get<std::string>()
       << ")'\nset termoption noenhanced\nset ylabel 'M [kg]'\nset grid\nset key top left\n";
    for (size_t i = 0; i < n; ++i) {
        gp << "set xlabel '" << c_.params[i].key << "'\nset xrange [" << c_.params[i].lo << ':' << c_.params[i].hi << "]\nplot ";
        for (size_t k = 0; k < c_.targets.size(); ++k) {
            const auto& t = c_.targets[k];
            gp << (k ? ", " : "") << "'calibration.dat' index " << k << " using " << i + 1 << ':' << n + 1
               << " with points pt " << 7 + k << " ps 1.5 title 'runs, " << targetLabel(t) << "', "
               << t.loadingKg * (1 - t.tol) << " with lines dt 2 lc " << k + 1 << " notitle, " << t.loadingKg
               << " with lines lc " << k + 1 << " title 'target " << formatNumber(t.loadingKg) << " kg +- "
               << formatNumber(100 * t.tol) << "%', " << t.loadingKg * (1 + t.tol) << " with lines dt 2 lc " << k + 1
               << " notitle";
        }
        gp << '\n';
    }
    gp << "unset multiplot\n";
    writeFileAtomic(dir / "calibration.csv", csv.str());
    writeFileAtomic(dir / "calibration.md", md.str());
    if (!evals.empty()) {
        const std::string warn = runGnuplot(dir, "calibration.gp", gp.str());
        if (!warn.empty()) std::cerr << "mixload: " << warn << '\n';
    }
    writeFileAtomic(dir / "calibration.json", j.dump(2));
}

}  // namespace

std::optional<double> depositFor(const std::vector<std::vector<double>>& xs, const std::vector<double>& loadings,
                                 const std::vector<double>& x, const std::vector<CalibrationBound>& bounds) {
    if (xs.size() < 2) return std::nullopt;
    const auto scaled = [&](const std::vector<double>& a, size_t i) { return a[i] / (bounds[i].hi - bounds[i].lo); };
    std::vector<size_t> order(xs.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    const auto dist = [&](size_t j) {
        double d = 0;
        for (size_t i = 0; i < x.size(); ++i) d += std::pow(scaled(xs[j], i) - scaled(x, i), 2);
        return d;
    };
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return dist(a) < dist(b); });
    double m = loadings[order[0]];
    if (x.size() == 1) {
        // Interpolate between the nearest points on either side; beyond them, extrapolate from the
        // two nearest on the one side.
        std::vector<size_t> byX(order);
        std::sort(byX.begin(), byX.end(), [&](size_t i, size_t j) { return xs[i][0] < xs[j][0]; });
        size_t hi = 0;
        while (hi < byX.size() && xs[byX[hi]][0] < x[0]) ++hi;
        const size_t i1 = hi == 0 ? 0 : hi == byX.size() ? byX.size() - 2 : hi - 1;
        const size_t a = byX[i1], b = byX[i1 + 1];
        if (xs[b][0] != xs[a][0])
            m = loadings[a] + (loadings[b] - loadings[a]) * (x[0] - xs[a][0]) / (xs[b][0] - xs[a][0]);
    }
    if (!(m > 0)) m = *std::min_element(loadings.begin(), loadings.end());
    return roundSignificant(m, 3);
}

CalibrationBound parseCalibrationParam(const std::string& text) {
    const auto eq = text.find('=');
    const std::string key = text.substr(0, eq);
    if (eq == std::string::npos || key.find('.') == std::string::npos)
        throw InputError("param", text, "TABLE.KEY=LO:HI[:START], e.g. weir.chord_angle_deg=20:88");
    const auto parts = splitColons(text.substr(eq + 1));
    if (parts.size() < 2 || parts.size() > 3) throw InputError("param " + key, text.substr(eq + 1), "LO:HI[:START]");
    CalibrationBound b{key, number("param " + key, parts[0], text), number("param " + key, parts[1], text), 0};
    if (!(b.hi > b.lo)) throw InputError("param " + key, text.substr(eq + 1), "LO < HI");
    b.start = parts.size() == 3 ? number("param " + key, parts[2], text) : 0.5 * (b.lo + b.hi);
    requireRange("param " + key + " start", b.start, b.lo, b.hi);
    return b;
}

LoadingTarget parseLoadingTarget(const std::string& text) {
    const auto parts = splitColons(text);
    if (parts.size() < 3 || parts.size() > 4) throw InputError("target", text, "RPM:FEED_KG_H:LOADING_KG[:TOL]");
    LoadingTarget t{number("target", parts[0], text), number("target", parts[1], text),
                    number("target", parts[2], text), parts.size() == 4 ? number("target", parts[3], text) : 0.12};
    requireRange("target rpm", t.rpm, 0.0, 2000.0, false, true);
    requireRange("target feed", t.feedKgH, 0.0, 1000.0, false, true);
    requireRange("target loading", t.loadingKg, 0.0, 1e4, false, true);
    requireRange("target tol", t.tol, 0.0, 1.0, false, false);
    return t;
}

void validateCalibration(const MixerCalibration& c) {
    if (c.name.empty() || c.name.find_first_of("/\\ ") != std::string::npos)
        throw InputError("name", c.name, "a non-empty name without '/', '\\' or blanks");
    if (c.params.empty()) throw InputError("param", "<none>", "at least one --param TABLE.KEY=LO:HI");
    if (c.targets.empty()) throw InputError("target", "<none>", "at least one --target RPM:FEED:LOADING");
    requireRange("max-evals", c.fit.maxEvals, 1, 200);
    requireRange("stop-rms", c.fit.stopRms, 0.0, 1.0, false, true);
    requireRange("np", c.np, 1, 256);
    requireRange("max-hours", c.maxHours, 0, 1e5);
    for (const auto& p : c.params)
        if (c.sizeDeposit && p.key == "operation.initial_loading_kg")
            throw InputError("size-deposit", "given", "not with operation.initial_loading_kg as a parameter");
    for (size_t i = 0; i < c.params.size(); ++i)
        for (size_t j = 0; j < i; ++j)
            if (c.params[i].key == c.params[j].key) throw InputError("param", c.params[i].key, "each key once");
    // Both ends and the start must make a valid scene at every target: refuse now, not mid-fit.
    for (const auto& p : c.params)
        for (double v : {p.lo, p.hi, p.start})
            for (const auto& t : c.targets) sceneAt(c, {{p.key, v}}, t);
}

nlohmann::json runMixerCalibration(const MixerCalibration& c) {
    validateCalibration(c);
    Driver d(c);
    CalibrationTrace last;
    const auto onEval = [&](const CalibrationTrace& t) {
        last = t;
        d.writeReport(d.report(t, "in-progress"));
        if (c.progress) {
            std::cerr << "calibration " << c.name << ": evaluation " << t.x.size() - 1 << " rms residual "
                      << formatNumber(t.rms.back()) << '\n';
        }
    };
    CalibrationTrace t;
    try {
        CalibrationOptions fit = c.fit;
        fit.residuals = static_cast<int>(c.targets.size());
        t = calibrate(c.params, [&](const std::vector<double>& x) { return d.residuals(x); }, fit, onEval);
    } catch (const DeadlineReached&) {
        last.stop = "max-hours";
        nlohmann::json j = d.report(last, "stopped-at-max-hours");
        d.writeReport(j);
        return j;
    }
    nlohmann::json j = d.report(t, maxAbs(t.r[t.best]) <= 1 ? "within-band" : "outside-band");
    d.writeReport(j);
    return j;
}

}  // namespace mixload::experiments
