// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload calibrate mixer`: parses the fit's options and prints its report; the driver is
// experiments/calibrate/mixer_calibration.
#include <iostream>

#include "app/commands.hpp"
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
