// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload calibrate mixer|collapse`: parses the fits' options and prints their reports; the
// drivers are experiments/calibrate/mixer_calibration and collapse_calibration.
#include <iostream>

#include "app/collapse_options.hpp"
#include "app/commands.hpp"
#include "calibrate/collapse_calibration.hpp"
#include "app/mixer_options.hpp"
#include "calibrate/mixer_calibration.hpp"
#include "common/input_error.hpp"

namespace mixload::app {

namespace {
struct CalibrateCmd {
    MixerOptions scene;
    std::string name, dir = "calibrations";
    std::vector<std::string> params, targets;
    int maxEvals = 12, np = 1;
    double stopRms = 0.25, maxHours = 0;
    bool allowUnsteady = false, sizeDeposit = false, json = false;
};

struct CalibrateCollapseCmd {
    CollapseOptions scene;
    std::string name, dir = "calibrations", data, law;
    std::vector<std::string> params;
    std::vector<double> aspects;
    int maxEvals = 12, jobs = 1;
    double stopRms = 0.5, maxHours = 0, checkAspect = 0.5;
    bool json = false;
};

void printCollapse(const nlohmann::json& r) {
    std::cout << "collapse calibration " << r["calibration"].get<std::string>() << ": " << r["status"].get<std::string>()
              << " (stop: " << r["stop"].get<std::string>() << "), " << r["evaluations"].size() << " evaluations, "
              << r["runs_new"] << " new runs, " << r["runs_reused"] << " from the ledger\n";
    if (r.contains("best")) {
        std::cout << "  best:";
        for (const auto& [k, v] : r["best"]["keys"].items()) std::cout << ' ' << k << " = " << formatNumber(v.get<double>());
        std::cout << " (rms residual " << formatNumber(r["best"]["rms"].get<double>()) << " standard uncertainties)\n";
        for (const auto& run : r["best"]["runs"]) {
            std::cout << "    a = " << formatNumber(run["aspect"].get<double>()) << ": L*f = "
                      << formatNumber(run["runout_star"].get<double>());
            if (run.contains("residual_runout")) std::cout << " (" << formatNumber(run["residual_runout"].get<double>()) << ")";
            std::cout << ", H*f = " << formatNumber(run["height_star"].get<double>());
            if (run.contains("residual_height")) std::cout << " (" << formatNumber(run["residual_height"].get<double>()) << ")";
            std::cout << '\n';
        }
        const auto& w = r["best_well_posedness"];
        std::cout << "  well-posed window (standard convention): "
                  << (w["window"].get<bool>() ? formatNumber(w["i_lower"].get<double>()) + " < I < " +
                                                    formatNumber(w["i_upper"].get<double>())
                                              : std::string("none"))
                  << '\n';
    }
    if (r.contains("check"))
        std::cout << "  check at a = " << formatNumber(r["check"]["aspect"].get<double>()) << ": H*f = "
                  << formatNumber(r["check"]["height_star"].get<double>()) << " ("
                  << (r["check"]["keeps_height"].get<bool>() ? "keeps" : "does not keep") << " its height)\n";
    std::cout << "  report " << (std::filesystem::path(r["ledger"].get<std::string>()).parent_path() / "report")
              << " (calibration.md, .csv, .png)\n";
    if (r["status"] == "stopped-at-max-hours") std::cout << "  stopped at --max-hours; run again to continue\n";
}

void addCalibrateCollapse(CLI::App* top, Action& action) {
    auto* cmd = top->add_subcommand(
        "collapse",
        "Fit the mu(I) coefficients (and the viscosity cap) so that 2D collapse runs meet final runouts and "
        "heights over a range of aspect ratios, given as a CSV of measurements or a shipped published law; "
        "every run is recorded in a resumable ledger");
    auto o = std::make_shared<CalibrateCollapseCmd>();
    o->scene.add(cmd);
    cmd->add_option("--name", o->name, "Calibration name: <dir>/<name>/ holds its ledger, runs and report")->required();
    cmd->add_option("--dir", o->dir, "Directory of calibrations")->capture_default_str();
    cmd->add_option("--param", o->params,
                    "A coefficient to fit and its bounds, KEY=LO:HI[:START][:log], KEY one of mu_s, mu_d, delta_mu "
                    "(mu_d - mu_s), i0, cap_h_ratio (Rauter's H / Hi), eta_max [Pa s]; repeatable")
        ->required();
    auto* data = cmd->add_option("--data", o->data,
                                 "CSV of measurements: aspect,runout_star,runout_sd,height_star,height_sd "
                                 "(one pair may be empty on a row)");
    auto* law = cmd->add_option("--law", o->law, "A shipped published law (data/collapse-laws: lube2005) or a .toml");
    cmd->add_option("--aspects", o->aspects, "With --law: the aspect ratios to fit at")->delimiter(',');
    data->excludes(law);
    cmd->add_option("--max-evals", o->maxEvals, "Most evaluations (each one run per aspect)")->capture_default_str();
    cmd->add_option("--stop-rms", o->stopRms,
                    "Stop once the rms of the residuals (in the data's standard uncertainties) is at most this")
        ->capture_default_str();
    cmd->add_option("--jobs", o->jobs, "Runs at a time within an evaluation")->capture_default_str();
    cmd->add_option("--check-aspect", o->checkAspect,
                    "The best fit at this aspect too (0: no; from the fit's own run when the data holds it): does it keep its height?")
        ->capture_default_str();
    cmd->add_option("--max-hours", o->maxHours, "Stop after this many hours (0: no limit); run again to continue")
        ->capture_default_str();
    cmd->add_flag("--json", o->json, "Print the report as JSON");
    cmd->callback([&action, o, cmd] {
        action = [o, cmd] {
            if (cmd->count("--aspect")) throw InputError("aspect", "given", "nothing: the data sets the aspects");
            experiments::CollapseCalibration c;
            c.name = o->name;
            c.dir = o->dir;
            for (const auto& p : o->params) c.params.push_back(experiments::parseCalibrationParam(p, false));
            if (!o->data.empty()) {
                if (!o->aspects.empty()) throw InputError("aspects", "given", "only with --law");
                c.data = experiments::readCollapseData(o->data);
            } else if (!o->law.empty()) {
                c.data = experiments::collapseDataFromLaw(experiments::loadCollapseLaw(o->law), o->aspects);
            } else {
                throw InputError("data", "<none>", "--data FILE or --law NAME --aspects A,B,...");
            }
            const scene::CollapseOverrides base = o->scene;
            c.sceneFor = [base](const std::map<std::string, double>& keys, double aspect) {
                scene::CollapseOverrides s = base;
                s.aspect = aspect;
                std::optional<double> deltaMu;
                for (const auto& [k, v] : keys) {
                    if (k == "mu_s") s.muS = v;
                    else if (k == "mu_d") s.muD = v;
                    else if (k == "delta_mu") deltaMu = v;
                    else if (k == "i0") s.I0 = v;
                    else if (k == "cap_h_ratio") s.capHeightRatio = v;
                    else if (k == "eta_max") s.etaMax = v;
                    else throw InputError("param", k, "mu_s|mu_d|delta_mu|i0|cap_h_ratio|eta_max");
                }
                // delta_mu keeps mu_d above mu_s wherever the search goes.
                if (deltaMu) {
                    s.muD.reset();
                    scene::CollapseScene sc = s.scene();
                    sc.material.muD = sc.material.muS + *deltaMu;
                    sc.validate();
                    return sc;
                }
                return s.scene();
            };
            c.fit.maxEvals = o->maxEvals;
            c.fit.stopRms = o->stopRms;
            c.jobs = o->jobs;
            c.checkAspect = o->checkAspect;
            c.maxHours = o->maxHours;
            c.progress = !o->json;
            const auto r = experiments::runCollapseCalibration(c);
            if (o->json) std::cout << r.dump(2) << '\n';
            else printCollapse(r);
            return r["status"] == "outside-uncertainty" ? 1 : 0;
        };
    });
}

void print(const nlohmann::json& r) {
    std::cout << "calibration " << r["calibration"].get<std::string>() << ": " << r["status"].get<std::string>()
              << " (stop: " << r["stop"].get<std::string>() << "), " << r["evaluations"].size() << " evaluations, "
              << r["runs_new"] << " new runs, " << r["runs_reused"] << " from the ledger\n";
    if (r.contains("best")) {
        std::cout << "  best:";
        for (const auto& [k, v] : r["best"]["keys"].items()) std::cout << ' ' << k << " = " << formatNumber(v.get<double>());
        std::cout << '\n';
        for (const auto& run : r["best"]["runs"])
            std::cout << "    M = " << formatNumber(run["loading_kg"].get<double>()) << " kg, residual "
                      << formatNumber(run["residual"].get<double>()) << " band widths"
                      << (run.value("steady", false) ? "" : " (NOT steady)") << "  " << run["run_dir"].get<std::string>()
                      << '\n';
    }
    std::cout << "  report " << (std::filesystem::path(r["ledger"].get<std::string>()).parent_path() / "report")
              << " (calibration.md, .csv, .png)\n";
    if (r["status"] == "stopped-at-max-hours") std::cout << "  stopped at --max-hours; run again to continue\n";
}
}  // namespace

void addCalibrate(CLI::App& app, Action& action) {
    auto* top = app.add_subcommand("calibrate", "Fit scene parameters to measured data with full runs");
    top->require_subcommand(1);
    addCalibrateCollapse(top, action);
    auto* cmd = top->add_subcommand(
        "mixer",
        "Fit scene-file keys (NLopt BOBYQA, bounded) so that the steady loading meets measured values at "
        "one or more operating points; every evaluation is a full run in a resumable ledger");
    auto o = std::make_shared<CalibrateCmd>();
    o->scene.add(cmd);
    cmd->add_option("--name", o->name, "Calibration name: <dir>/<name>/ holds its ledger, runs and report")
        ->required();
    cmd->add_option("--dir", o->dir, "Directory of calibrations")->capture_default_str();
    cmd->add_option("--param", o->params,
                    "A scene-file key to fit and its bounds, TABLE.KEY=LO:HI[:START] (start: the middle); "
                    "repeatable")
        ->required();
    cmd->add_option("--target", o->targets,
                    "A measured loading, RPM:FEED_KG_H:LOADING_KG[:TOL] (TOL relative, default 0.12, the "
                    "paper's band); repeatable")
        ->required();
    cmd->add_option("--max-evals", o->maxEvals, "Most evaluations (each one full run per target)")
        ->capture_default_str();
    cmd->add_option("--stop-rms", o->stopRms,
                    "Stop once the rms of the residuals (in band half-widths) is at most this")
        ->capture_default_str();
    cmd->add_flag("--allow-unsteady", o->allowUnsteady,
                  "Count runs that reach --end-time without a steady verdict (tests, quick looks)");
    cmd->add_flag("--size-deposit", o->sizeDeposit,
                  "From the third evaluation on, deposit the loading the evaluations so far predict there "
                  "(deep beds settle much sooner from near their loading)");
    cmd->add_option("--np", o->np, "MPI ranks per run")->capture_default_str();
    cmd->add_option("--max-hours", o->maxHours,
                    "Stop after this many hours (0: no limit); run again to continue")
        ->capture_default_str();
    cmd->add_flag("--json", o->json, "Print the report as JSON");
    cmd->callback([&action, o] {
        action = [o] {
            if (o->scene.rpm || o->scene.feedKgH)
                throw InputError("rpm/feed-kg-h", "given", "nothing: each --target sets the operating point");
            experiments::MixerCalibration c;
            c.name = o->name;
            c.dir = o->dir;
            for (const auto& p : o->params) c.params.push_back(experiments::parseCalibrationParam(p));
            for (const auto& t : o->targets) c.targets.push_back(experiments::parseLoadingTarget(t));
            const MixerOptions scene = o->scene;
            c.sceneFor = [scene](const scene::SceneKeys& keys) { return scene.build(keys); };
            c.fit.maxEvals = o->maxEvals;
            c.fit.stopRms = o->stopRms;
            c.allowUnsteady = o->allowUnsteady;
            c.sizeDeposit = o->sizeDeposit;
            c.np = o->np;
            c.maxHours = o->maxHours;
            c.progress = !o->json;
            const auto r = experiments::runMixerCalibration(c);
            if (o->json) std::cout << r.dump(2) << '\n';
            else print(r);
            return r["status"] == "outside-band" ? 1 : 0;
        };
    });
}

}  // namespace mixload::app
