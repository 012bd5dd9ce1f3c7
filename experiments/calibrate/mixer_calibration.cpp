// SPDX-License-Identifier: GPL-3.0-or-later
#include "calibrate/mixer_calibration.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "calibrate/calibration_runs.hpp"
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


namespace {

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
    explicit Driver(const MixerCalibration& c) : c_(c), runs_(c.dir, c.name, "calibrate mixer --name " + c.name, baseInfo(c), specOf(c), c.maxHours) {}

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
            nlohmann::json run = runs_.get(
                s.hash(), {{"keys", e.keys}, {"rpm", t.rpm}, {"feed_kg_h", t.feedKgH}}, targetLabel(t), "mixer", c_.np,
                [&](const fs::path& out) {
                    run::MixerJob job;
                    job.scene = s;
                    job.np = c_.np;
                    job.progress = c_.progress;
                    job.deadline = runs_.deadline();
                    job.out = out;
                    return run::runMixer(job);
                });
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
                         {"runs_new", runs_.newRuns()},
                         {"runs_reused", runs_.reusedRuns()},
                         {"ledger", runs_.ledgerFile().string()},
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
    static store::CampaignInfo baseInfo(const MixerCalibration& c) {
        store::CampaignInfo info;
        const auto base = c.sceneFor({});
        info.scene = "mixer";
        info.sceneHash = base.hash();
        info.sceneJson = base.toJson();
        info.method = base.method;
        info.mesh = base.meshLabel();
        return info;
    }

    const MixerCalibration& c_;
    CalibrationRuns runs_;
    std::vector<Evaluation> evals_;
};

void Driver::writeReport(const nlohmann::json& j) const {
    const fs::path dir = runs_.home() / "report";
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

LoadingTarget parseLoadingTarget(const std::string& text) {
    const auto parts = splitColons(text);
    if (parts.size() < 3 || parts.size() > 4) throw InputError("target", text, "RPM:FEED_KG_H:LOADING_KG[:TOL]");
    const auto num = [&](size_t i) { return parseFieldNumber("target", parts[i], text); };
    LoadingTarget t{num(0), num(1), num(2), parts.size() == 4 ? num(3) : 0.12};
    requireRange("target rpm", t.rpm, 0.0, 2000.0, false, true);
    requireRange("target feed", t.feedKgH, 0.0, 1000.0, false, true);
    requireRange("target loading", t.loadingKg, 0.0, 1e4, false, true);
    requireRange("target tol", t.tol, 0.0, 1.0, false, false);
    return t;
}

void validateCalibration(const MixerCalibration& c) {
    requireCalibrationName(c.name);
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
    CalibrationOptions fit = c.fit;
    fit.residuals = static_cast<int>(c.targets.size());
    const FitOutcome f = runFit(
        c.name, c.params, [&](const std::vector<double>& x) { return d.residuals(x); }, fit, c.progress,
        [&](const CalibrationTrace& t) { d.writeReport(d.report(t, "in-progress")); });
    const CalibrationTrace& t = f.trace;
    const nlohmann::json j = d.report(t, f.stopped                        ? "stopped-at-max-hours"
                                         : maxAbs(t.r[t.best]) <= 1 ? "within-band"
                                                                    : "outside-band");
    d.writeReport(j);
    return j;
}

}  // namespace mixload::experiments
