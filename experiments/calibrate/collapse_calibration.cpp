// SPDX-License-Identifier: GPL-3.0-or-later
#include "calibrate/collapse_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <iostream>
#include <sstream>

#include "calibrate/calibration_runs.hpp"
#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "common/process.hpp"
#include "mixload_version.hpp"
#include "muILaw.H"
#include "run/collapse_job.hpp"
#include "run/foam_runner.hpp"
#include "studies/run_pool.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

const std::vector<std::string>& collapseFitKeys() {
    static const std::vector<std::string> keys{"mu_s", "mu_d", "delta_mu", "i0", "cap_h_ratio", "eta_max"};
    return keys;
}

namespace {

using Keys = std::map<std::string, double>;

std::string aspectLabel(double a) { return "a = " + formatNumber(a); }

nlohmann::json specOf(const CollapseCalibration& c) {
    nlohmann::json params = nlohmann::json::array();
    for (const auto& p : c.params)
        params.push_back({{"key", p.key}, {"lo", p.lo}, {"hi", p.hi}, {"start", p.start}, {"log", p.log}});
    // The base scene at a = 1: every input but the aspect (and the fitted keys' start values).
    return {{"params", params}, {"data", c.data.toJson()}, {"base_scene_hash", c.sceneFor({}, 1.0).hash()}};
}

// The coefficients a scene runs with, in the standard convention, and their well-posed window.
nlohmann::json wellPosedness(double muS, double muD, double I0) {
    const auto w = rheology::wellPosedWindow({muS, muD, I0});
    nlohmann::json j{{"mu_s", muS}, {"mu_d", muD}, {"i0", I0}, {"window", w.exists}};
    if (w.exists) j["i_lower"] = w.lower, j["i_upper"] = w.upper;
    else j["least_ill_posed_i"] = w.leastIllPosedI;
    return j;
}

nlohmann::json wellPosednessOf(const scene::CollapseScene& s) {
    return wellPosedness(s.muSCase(), s.muDCase(), s.material.I0);
}

// The paper's collapse fits (its Table 2, its convention), read both ways.
nlohmann::json paperFits() {
    nlohmann::json out = nlohmann::json::array();
    const struct {
        const char* name;
        double muS, muD, I0;
    } fits[] = {{"quartz (paper)", 1.33, 1.69, 0.30}, {"copper (paper)", 1.22, 1.61, 0.34}};
    for (const auto& f : fits) {
        out.push_back({{"name", std::string(f.name) + ", as written, read in the standard convention"},
                       {"coefficients", wellPosedness(f.muS, f.muD, f.I0)}});
        out.push_back({{"name", std::string(f.name) + ", converted from its convention (mu / sqrt 2)"},
                       {"coefficients", wellPosedness(f.muS / std::sqrt(2.0), f.muD / std::sqrt(2.0), f.I0)}});
    }
    return out;
}

struct Evaluation {
    Keys keys;
    std::vector<nlohmann::json> runs;  // per data point
};

class Driver {
public:
    explicit Driver(const CollapseCalibration& c)
        : c_(c), runs_(c.dir, c.name, "calibrate collapse --name " + c.name, baseInfo(c), specOf(c), c.maxHours) {}

    std::vector<double> residuals(const std::vector<double>& x) {
        Evaluation e;
        for (size_t i = 0; i < x.size(); ++i) e.keys[c_.params[i].key] = roundSignificant(x[i], 6);
        e.runs = runAll(e.keys, aspects());
        std::vector<double> r;
        for (size_t i = 0; i < c_.data.points.size(); ++i) {
            const auto& p = c_.data.points[i];
            auto& run = e.runs[i];
            if (p.runout) {
                run["residual_runout"] = standardResidual(run["runout_star"].get<double>(), *p.runout, *p.runoutSd);
                r.push_back(run["residual_runout"].get<double>());
            }
            if (p.height) {
                run["residual_height"] = standardResidual(run["height_star"].get<double>(), *p.height, *p.heightSd);
                r.push_back(run["residual_height"].get<double>());
            }
        }
        evals_.push_back(e);
        return r;
    }

    // The best coefficients at the check aspect (from the ledger when the data holds that aspect).
    std::optional<nlohmann::json> check(const Keys& best) {
        if (c_.checkAspect <= 0) return std::nullopt;
        return runAll(best, {c_.checkAspect}).front();
    }

    nlohmann::json report(const CalibrationTrace& t, const std::string& status,
                          const std::optional<nlohmann::json>& checkRun) const {
        nlohmann::json evals = nlohmann::json::array();
        for (size_t i = 0; i < evals_.size() && i < t.rms.size(); ++i)
            evals.push_back({{"keys", evals_[i].keys}, {"runs", evals_[i].runs}, {"rms", t.rms[i]}});
        nlohmann::json j{{"calibration", c_.name},
                         {"status", status},
                         {"stop", t.stop},
                         {"evaluations", evals},
                         {"data", c_.data.toJson()},
                         {"runs_new", runs_.newRuns()},
                         {"runs_reused", runs_.reusedRuns()},
                         {"ledger", runs_.ledgerFile().string()},
                         {"spec", specOf(c_)},
                         {"paper_fits", paperFits()},
                         {"mixload_version", kVersion},
                         {"git_commit", kGitCommit}};
        if (!evals.empty()) {
            j["best"] = evals[t.best];
            j["best_evaluation"] = t.best;
            double m = 0;
            for (double v : t.r[t.best]) m = std::max(m, std::abs(v));
            j["best_max_residual"] = m;
            j["best_well_posedness"] = wellPosednessOf(c_.sceneFor(evals_[t.best].keys, 1.0));
        }
        if (checkRun) {
            nlohmann::json ck = *checkRun;
            ck["aspect"] = c_.checkAspect;
            // Keeps its height: the top of the column did not move, to a cell.
            const auto s = c_.sceneFor(evals_[t.best].keys, c_.checkAspect);
            ck["keeps_height"] = ck["height_star"].get<double>() >= 1.0 - s.dx() / s.height();
            j["check"] = ck;
        }
        return j;
    }

    void writeReport(const nlohmann::json& j) const;

private:
    std::vector<double> aspects() const {
        std::vector<double> a;
        for (const auto& p : c_.data.points) a.push_back(p.aspect);
        return a;
    }

    // The collapse at each aspect with these keys: from the ledger, or run (jobs at a time).
    std::vector<nlohmann::json> runAll(const Keys& keys, const std::vector<double>& aspects) {
        std::vector<nlohmann::json> out(aspects.size());
        struct Pending {
            size_t i;
            scene::CollapseScene s;
            store::LedgerRun row;
            fs::path dir;
        };
        std::vector<Pending> pending;
        for (size_t i = 0; i < aspects.size(); ++i) {
            const auto s = c_.sceneFor(keys, aspects[i]);
            if (auto q = runs_.finished(s.hash(), aspectLabel(aspects[i]))) out[i] = *q;
            else {
                const auto row = runs_.claim(s.hash(), {{"keys", keys}, {"aspect", aspects[i]}});
                pending.push_back({i, s, row, runs_.runDir(row, s.hash())});
            }
        }
        struct Outcome {
            nlohmann::json result;
            std::exception_ptr error;
        };
        std::exception_ptr first, deadline;
        runPool<Outcome>(
            pending.size(), c_.jobs, "calibration " + c_.name, c_.progress && pending.size() > 1,
            [&](size_t k) {
                run::CollapseJob job;
                job.scene = pending[k].s;
                job.out = pending[k].dir;
                job.deadline = runs_.deadline();
                job.progress = c_.progress && pending.size() == 1;
                try {
                    return Outcome{run::runCollapse(job), nullptr};
                } catch (...) {
                    return Outcome{{}, std::current_exception()};
                }
            },
            [&](size_t k, const Outcome& o) {
                const auto& p = pending[k];
                if (!o.error) {
                    out[p.i] = runs_.done(p.row, "collapse", o.result, p.dir, 1);
                    return;
                }
                try {
                    std::rethrow_exception(o.error);
                } catch (const DeadlineReached&) {
                    runs_.stopped(p.row);
                    if (!deadline) deadline = o.error;
                } catch (const std::exception& e) {
                    runs_.failed(p.row, e.what());
                    if (!first) first = o.error;
                }
            });
        if (first) std::rethrow_exception(first);
        if (deadline) std::rethrow_exception(deadline);
        for (size_t i = 0; i < aspects.size(); ++i) out[i]["aspect"] = aspects[i];
        return out;
    }

    static store::CampaignInfo baseInfo(const CollapseCalibration& c) {
        store::CampaignInfo info;
        const auto base = c.sceneFor({}, 1.0);
        info.scene = "collapse";
        info.sceneHash = base.hash();
        info.sceneJson = base.toJson();
        info.method = base.rheology;
        info.mesh = "Li/" + std::to_string(base.cellsPerLength);
        return info;
    }

    const CollapseCalibration& c_;
    CalibrationRuns runs_;
    std::vector<Evaluation> evals_;
};

std::string windowText(const nlohmann::json& w) {
    if (w["window"].get<bool>())
        return "well-posed for " + sig4(w["i_lower"].get<double>()) + " < I < " + sig4(w["i_upper"].get<double>());
    return "no well-posed window (least ill-posed at I = " + sig4(w["least_ill_posed_i"].get<double>()) + ")";
}

void Driver::writeReport(const nlohmann::json& j) const {
    const fs::path dir = runs_.home() / "report";
    fs::create_directories(dir);
    std::ostringstream csv, md, dat;
    const auto& evals = j["evaluations"];
    csv << "eval";
    for (const auto& p : c_.params) csv << ',' << p.key;
    csv << ",rms\n";
    md << "# Collapse calibration " << c_.name << "\n\nstatus: **" << j["status"].get<std::string>() << "** (stop: "
       << j["stop"].get<std::string>() << "); " << j["runs_new"] << " new runs, " << j["runs_reused"]
       << " from the ledger; mixload " << kVersion << " (" << kGitCommit << ")\n\nData: " << c_.data.source
       << "\n\nResiduals are (model - data) / (the data's standard uncertainty); the fit minimises their mean "
          "square.\n\n| eval |";
    for (const auto& p : c_.params) md << ' ' << p.key << " |";
    md << " rms |\n|---|";
    for (size_t i = 0; i <= c_.params.size(); ++i) md << "---|";
    md << '\n';
    for (size_t i = 0; i < evals.size(); ++i) {
        csv << i;
        md << "| " << i << " |";
        for (const auto& p : c_.params) {
            csv << ',' << evals[i]["keys"][p.key].get<double>();
            md << ' ' << sig4(evals[i]["keys"][p.key].get<double>()) << " |";
        }
        csv << ',' << evals[i]["rms"].get<double>() << '\n';
        md << ' ' << sig4(evals[i]["rms"].get<double>()) << " |\n";
    }
    // Data, then the first and the best evaluation: one gnuplot block each.
    for (const auto& p : c_.data.points)
        dat << p.aspect << ' ' << (p.runout ? *p.runout : NAN) << ' ' << (p.runoutSd ? *p.runoutSd : NAN) << ' '
            << (p.height ? *p.height : NAN) << ' ' << (p.heightSd ? *p.heightSd : NAN) << '\n';
    dat << "\n\n";
    const auto block = [&](const nlohmann::json& e) {
        for (const auto& r : e["runs"])
            dat << r["aspect"].get<double>() << ' ' << r["runout_star"].get<double>() << " 0 "
                << r["height_star"].get<double>() << " 0\n";
        dat << "\n\n";
    };
    if (j.contains("best")) {
        const auto& b = j["best"];
        md << "\n## Best fit (evaluation " << j["best_evaluation"] << ")\n\n";
        std::string sep;
        for (const auto& [k, v] : b["keys"].items()) md << sep << k << " = " << sig4(v.get<double>()), sep = ", ";
        md << "; rms residual " << sig4(b["rms"].get<double>()) << ".\n\n| a | L*f data | L*f model | residual | H*f data | H*f model | residual | stopped by | powder volume error |\n"
              "|---|---|---|---|---|---|---|---|---|\n";
        for (size_t i = 0; i < c_.data.points.size(); ++i) {
            const auto& p = c_.data.points[i];
            const auto& r = b["runs"][i];
            md << "| " << sig4(p.aspect) << " | "
               << (p.runout ? sig4(*p.runout) + " ± " + sig4(*p.runoutSd) : std::string("–")) << " | "
               << sig4(r["runout_star"].get<double>()) << " | "
               << (r.contains("residual_runout") ? sig4(r["residual_runout"].get<double>()) : std::string("–")) << " | "
               << (p.height ? sig4(*p.height) + " ± " + sig4(*p.heightSd) : std::string("–")) << " | "
               << sig4(r["height_star"].get<double>()) << " | "
               << (r.contains("residual_height") ? sig4(r["residual_height"].get<double>()) : std::string("–")) << " | "
               << r.value("stopped_by", std::string("?")) << " | " << sig4(r.value("powder_mass_error", 0.0)) << " |\n";
        }
        md << "\nWell-posedness of the best coefficients (standard convention, Barker et al. 2015): "
           << windowText(j["best_well_posedness"]) << ".\n";
        block(evals.front());
        block(b);
    }
    if (j.contains("check")) {
        const auto& ck = j["check"];
        dat << ck["aspect"].get<double>() << ' ' << ck["runout_star"].get<double>() << " 0 " << ck["height_star"].get<double>()
            << " 0\n\n\n";
        md << "\nCheck run at a = " << sig4(ck["aspect"].get<double>()) << " with the best coefficients: H*f = "
           << sig4(ck["height_star"].get<double>()) << ", L*f = " << sig4(ck["runout_star"].get<double>())
           << " (stopped by " << ck.value("stopped_by", std::string("?")) << "): the column "
           << (ck["keeps_height"].get<bool>() ? "keeps" : "does not keep") << " its height.\n";
    }
    md << "\n## The paper's collapse fits, for comparison\n\n| fit | mu_s | mu_d | I0 | well-posedness |\n|---|---|---|---|---|\n";
    for (const auto& f : j["paper_fits"]) {
        const auto& w = f["coefficients"];
        md << "| " << f["name"].get<std::string>() << " | " << sig4(w["mu_s"].get<double>()) << " | "
           << sig4(w["mu_d"].get<double>()) << " | " << sig4(w["i0"].get<double>()) << " | " << windowText(w) << " |\n";
    }
    writeFileAtomic(dir / "calibration.dat", dat.str());
    writeFileAtomic(dir / "calibration.csv", csv.str());
    writeFileAtomic(dir / "calibration.md", md.str());
    if (j.contains("best")) {
        std::ostringstream gp;
        const std::string checkPlot = j.contains("check") ? ", '' index 3 using 1:COL with points pt 6 ps 2 lc 'red' title 'best fit, check run'" : "";
        const auto withCol = [&](char col) {
            std::string p = checkPlot;
            if (!p.empty()) p.replace(p.find("COL"), 3, std::string(1, col));
            return p;
        };
        gp << "set terminal pngcairo size 1100,440 noenhanced\nset output 'calibration.png'\nset offsets graph 0.05, graph 0.05, graph 0.05, graph 0.05\n"
           << "set multiplot layout 1,2 title 'collapse calibration " << c_.name << " ("
           << j["status"].get<std::string>() << ")'\nset grid\nset key left top\nset xlabel 'aspect ratio a = Hi/Li'\n"
           << "set ylabel 'L*f = (Lf - Li)/Li'\nplot 'calibration.dat' index 0 using 1:2:3 with yerrorbars pt 7 "
              "lc 'black' title 'data', '' index 1 using 1:2 with linespoints dt 2 lc 'gray' title 'first "
              "evaluation', '' index 2 using 1:2 with linespoints lw 2 lc 'red' title 'best fit'" << withCol('2') << "\n"
           << "set ylabel 'H*f = Hf/Hi'\nset key right top\nset yrange [0:1.1]\nplot 'calibration.dat' index 0 "
              "using 1:4:5 with yerrorbars pt 7 lc 'black' title 'data', '' index 1 using 1:4 with linespoints dt 2 "
              "lc 'gray' title 'first evaluation', '' index 2 using 1:4 with linespoints lw 2 lc 'red' title 'best "
              "fit'" << withCol('4') << "\nunset multiplot\n";
        const std::string warn = runGnuplot(dir, "calibration.gp", gp.str());
        if (!warn.empty()) std::cerr << "mixload: " << warn << '\n';
    }
    writeFileAtomic(dir / "calibration.json", j.dump(2));
}

}  // namespace

void validateCollapseCalibration(const CollapseCalibration& c) {
    requireCalibrationName(c.name);
    if (c.params.empty()) throw InputError("param", "<none>", "at least one --param KEY=LO:HI (mu_s, mu_d, delta_mu, i0, cap_h_ratio, eta_max)");
    if (c.data.points.empty()) throw InputError("data", "<none>", "--data FILE or --law NAME");
    requireRange("max-evals", c.fit.maxEvals, 1, 200);
    requireRange("stop-rms", c.fit.stopRms, 0.0, 10.0, false, true);
    requireRange("jobs", c.jobs, 1, 64);
    requireRange("max-hours", c.maxHours, 0, 1e5);
    requireRange("check-aspect", c.checkAspect, 0.0, 10.0);
    bool cap = false, eta = false, muD = false, delta = false;
    for (size_t i = 0; i < c.params.size(); ++i) {
        const auto& k = c.params[i].key;
        if (std::find(collapseFitKeys().begin(), collapseFitKeys().end(), k) == collapseFitKeys().end())
            throw InputError("param", k, "mu_s|mu_d|delta_mu|i0|cap_h_ratio|eta_max");
        for (size_t j = 0; j < i; ++j)
            if (c.params[j].key == k) throw InputError("param", k, "each key once");
        cap = cap || k == "cap_h_ratio";
        eta = eta || k == "eta_max";
        muD = muD || k == "mu_d";
        delta = delta || k == "delta_mu";
    }
    if (cap && eta) throw InputError("param", "cap_h_ratio and eta_max", "one of the two caps");
    if (muD && delta) throw InputError("param", "mu_d and delta_mu", "one of the two");
    // Both ends and the start of each range must make a valid scene at every aspect: refuse now.
    std::vector<double> aspects;
    for (const auto& p : c.data.points) aspects.push_back(p.aspect);
    if (c.checkAspect > 0) aspects.push_back(c.checkAspect);
    for (const auto& p : c.params)
        for (double v : {p.lo, p.hi, p.start})
            for (double a : aspects) c.sceneFor({{p.key, v}}, a);
}

nlohmann::json runCollapseCalibration(const CollapseCalibration& c) {
    validateCollapseCalibration(c);
    Driver d(c);
    // One parameter against one value is a root search; anything else goes to BOBYQA.
    CalibrationOptions fit = c.fit;
    fit.residuals = 0;
    for (const auto& p : c.data.points) fit.residuals += (p.runout ? 1 : 0) + (p.height ? 1 : 0);
    FitOutcome f = runFit(
        c.name, c.params, [&](const std::vector<double>& x) { return d.residuals(x); }, fit, c.progress,
        [&](const CalibrationTrace& t) { d.writeReport(d.report(t, "in-progress", std::nullopt)); });
    const CalibrationTrace& t = f.trace;
    std::optional<nlohmann::json> checkRun;
    if (!f.stopped) {
        Keys best;
        for (size_t i = 0; i < c.params.size(); ++i) best[c.params[i].key] = roundSignificant(t.x[t.best][i], 6);
        try {
            checkRun = d.check(best);
        } catch (const DeadlineReached&) {
            f.stopped = true;
        }
    }
    const nlohmann::json j = d.report(t, f.stopped                  ? "stopped-at-max-hours"
                                         : t.rms[t.best] <= 1 ? "within-uncertainty"
                                                              : "outside-uncertainty",
                                      checkRun);
    d.writeReport(j);
    return j;
}

}  // namespace mixload::experiments
