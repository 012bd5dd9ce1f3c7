// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload rom`: reduced-order models on stored snapshots. `rom pod` builds a POD basis.
#include <sys/resource.h>

#include <chrono>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "app/commands.hpp"
#include "common/clock.hpp"
#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "campaign/campaign.hpp"
#include "campaign/campaign_table.hpp"
#include "rom/regression/campaign_regression.hpp"
#include "rom/steady/steady_loading.hpp"
#include "rom/galerkin/collapse_check.hpp"
#include "rom/galerkin/collapse_galerkin.hpp"
#include "rom/galerkin/collapse_model_file.hpp"
#include "rom/pod/pod_model.hpp"
#include "rom/hyper/viscosity_deim.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::app {

namespace fs = std::filesystem;

namespace {
struct PodCmd {
    std::vector<std::string> files, fields{"alpha"};
    std::string campaign, dir = "runs/campaigns", output;
    int modes = 0, deimModes = 10;
    std::string plot;
    double energy = 0.9999;
    bool noMean = false, json = false, logSpace = false;
};

// The files named, or a campaign's: one of the two.
std::vector<fs::path> snapshotFiles(const PodCmd& o) {
    if (o.files.empty() == o.campaign.empty())
        throw InputError("FILES", o.files.empty() ? "(none)" : "with --campaign", "snapshot files or --campaign NAME, not both");
    return o.campaign.empty() ? std::vector<fs::path>(o.files.begin(), o.files.end())
                              : store::campaignSnapshotFiles(fs::path(o.dir) / o.campaign / "ledger.sqlite", o.campaign);
}

double peakRssBytes() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return 1024.0 * static_cast<double>(u.ru_maxrss);
}

// The spectrum beside the basis: lambda_k / sum(lambda) and the energy left out after k modes.
std::string plotSpectrum(const rom::PodModel& m, const fs::path& out) {
    const auto& l = m.basis.eigenvalues;
    const double total = l.sum();
    std::ostringstream dat;
    double left = total;
    for (Eigen::Index k = 0; k < l.size(); ++k) {
        left -= l[k];
        // Below round-off a share is noise: not drawn.
        const auto share = [](double v) {
            std::ostringstream os;
            os << std::setprecision(10) << v;
            return v > 1e-15 ? os.str() : std::string("NaN");
        };
        dat << k + 1 << ' ' << share(l[k] / total) << ' ' << share(left / total) << '\n';
    }
    const fs::path dir = fs::absolute(out).parent_path();
    const std::string stem = out.stem().string();
    writeFileAtomic(dir / (stem + ".spectrum.dat"), dat.str());
    std::ostringstream gp;
    gp << "set terminal pngcairo size 800,560\nset output '" << stem << ".spectrum.png'\n"
       << "set datafile missing 'NaN'\nset logscale y\nset format y '10^{%L}'\nset xlabel 'mode k'\nset ylabel 'share of the fluctuation energy'\n"
       << "set title 'POD of " << m.basis.snapshots << " snapshots (" << fs::path(out).filename().string()
       << "): " << m.basis.modes.cols() << " modes kept'\nset grid\nset key top right\n"
       << "set arrow from " << m.basis.modes.cols() + 0.5 << ", graph 0 to " << m.basis.modes.cols() + 0.5
       << ", graph 1 nohead dt 2\n"
       << "plot '" << stem << ".spectrum.dat' u 1:2 w lp pt 7 ps 0.6 t 'lambda_k / sum lambda', '' u 1:3 w l lw 2 t "
          "'left out after k modes'\n";
    return runGnuplot(dir, stem + ".spectrum.gp", gp.str());
}
// Training and hold-out errors (mean and worst) against the number of DEIM points.
std::string plotDeim(const nlohmann::json& j, const fs::path& png) {
    std::ostringstream dat;
    for (const auto& r : j["by_modes"]) {
        dat << r["modes"] << ' ' << std::max(r["train"]["mean"].get<double>(), 1e-16) << ' '
            << std::max(r["train"]["max"].get<double>(), 1e-16);
        if (r["holdout"].is_null()) dat << " NaN NaN\n";
        else dat << ' ' << r["holdout"]["mean"].get<double>() << ' ' << r["holdout"]["max"].get<double>() << '\n';
    }
    const fs::path dir = fs::absolute(png).parent_path();
    const std::string stem = png.stem().string();
    writeFileAtomic(dir / (stem + ".dat"), dat.str());
    std::ostringstream gp;
    gp << "set terminal pngcairo size 800,520\nset output '" << png.filename().string() << "'\n"
       << "set datafile missing 'NaN'\nset logscale y\nset format y '10^{%L}'\nset grid\n"
       << "set xlabel 'DEIM points'\nset ylabel 'relative L2 error of nu'\n"
       << "set title 'DEIM of the mu(I) viscosity: " << j["train_snapshots"] << " training, " << j["holdout_snapshots"]
       << " held-out snapshots'\nset arrow from graph 0, first 0.01 to graph 1, first 0.01 nohead dt 2\n"
       << "plot '" << stem << ".dat' u 1:4 w lp pt 7 ps 0.5 t 'hold-out, mean', '' u 1:5 w l t 'hold-out, worst', "
       << "'' u 1:2 w l dt 3 t 'training, mean'\n";
    return runGnuplot(dir, stem + ".gp", gp.str());
}

// L*(t) and H*(t) of the model against the full run, for each checked run.
std::string plotGalerkin(const nlohmann::json& checks, double tStar, const fs::path& png) {
    const fs::path dir = fs::absolute(png).parent_path();
    const std::string stem = png.stem().string();
    std::ostringstream plotL, plotH;
    for (size_t k = 0; k < checks.size(); ++k) {
        const auto& j = checks[k];
        std::ostringstream dat;
        for (const auto& r : j["times"])
            dat << r["t"].get<double>() / tStar << ' ' << r["runout_star"] << ' ' << r["runout_star_full"] << ' '
                << r["height_star"] << ' ' << r["height_star_full"] << '\n';
        const std::string name = stem + "." + std::to_string(k) + ".dat";
        writeFileAtomic(dir / name, dat.str());
        std::ostringstream label;
        label << std::setprecision(3) << "mu_s " << j["mu_s"].get<double>() << ", I0 " << j["i0"].get<double>()
              << (j["trained_on_this_run"].get<bool>() ? " (trained)" : " (held out)");
        const std::string sep = k ? ", " : "";
        plotL << sep << "'" << name << "' u 1:3 w l lw 2 lc " << k + 1 << " t 'full, " << label.str() << "', '' u 1:2 w l dt 2 lw 2 lc "
              << k + 1 << " t 'ROM'";
        plotH << sep << "'" << name << "' u 1:5 w l lw 2 lc " << k + 1 << " notitle, '' u 1:4 w l dt 2 lw 2 lc " << k + 1 << " notitle";
    }
    std::ostringstream gp;
    gp << "set terminal pngcairo size 1100,480\nset output '" << png.filename().string() << "'\nset grid\n"
       << "set multiplot layout 1,2 title 'POD-Galerkin collapse (dashed) against the full run (solid)'\n"
       << "set xlabel 't / t*'\nset ylabel 'L* = (L - Li) / Li'\nset key bottom right font ',8'\nplot " << plotL.str()
       << "\nset ylabel 'H* = H / Hi'\nplot " << plotH.str() << "\nunset multiplot\n";
    return runGnuplot(dir, stem + ".gp", gp.str());
}

}  // namespace

void addRom(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand("rom", "Reduced-order models on stored snapshots: POD, DEIM, the POD-Galerkin collapse (build, check, run), POD regression (see README, Reduced models)");
    cmd->require_subcommand(1);
    auto o = std::make_shared<PodCmd>();
    auto* pod = cmd->add_subcommand(
        "pod", "POD basis (method of snapshots, cell-volume weights) of snapshot files of one mesh, written to HDF5");
    pod->add_option("FILES", o->files, "Snapshot files (mixload snapshots export, or runs with --snapshots)");
    pod->add_option("--campaign", o->campaign, "Use the snapshot files of this campaign's finished runs instead");
    pod->add_option("--dir", o->dir, "Campaign directory (with --campaign)")->capture_default_str();
    pod->add_option("--field", o->fields, "Stored field(s): one gives its own basis, several a coupled one (each "
                                          "field weighted by its fluctuation energy); repeatable")
        ->capture_default_str();
    pod->add_option("--modes", o->modes, "At most this many modes (0: as --energy says)")->capture_default_str();
    pod->add_option("--energy", o->energy, "Keep the fewest modes holding this share of the fluctuation energy, in (0, 1]")
        ->capture_default_str();
    pod->add_flag("--no-mean", o->noMean, "Do not subtract the snapshots' mean");
    pod->add_option("-o,--output", o->output, "Basis file (.h5); a spectrum PNG is written beside it")->required();
    pod->add_flag("--json", o->json, "Print the summary as JSON");
    pod->callback([&action, o] {
        action = [o] {
            const auto files = snapshotFiles(*o);
            rom::PodOptions opt;
            opt.maxModes = o->modes;
            opt.energy = o->energy;
            opt.subtractMean = !o->noMean;
            requireRange("energy", o->energy, 0.0, 1.0, false, true);
            requireRange("modes", o->modes, 0, 1e6);
            const auto t0 = std::chrono::steady_clock::now();
            const store::SnapshotSet set(files);
            const auto m = rom::buildPod(set, o->fields, opt);
            rom::writePod(m, o->output);
            const double wall = secondsSince(t0);
            const std::string warn = plotSpectrum(m, o->output);
            const auto& b = m.basis;
            std::vector<double> spectrum;
            for (Eigen::Index k = 0; k < std::min<Eigen::Index>(b.eigenvalues.size(), 20); ++k)
                spectrum.push_back(b.eigenvalues[k] / b.totalEnergy());
            nlohmann::json j{{"file", fs::absolute(o->output).string()},
                             {"spectrum_png", (fs::absolute(o->output).parent_path() / (fs::path(o->output).stem().string() + ".spectrum.png")).string()},
                             {"fields", m.fields},
                             {"files", set.files().size()},
                             {"snapshots", b.snapshots},
                             {"cells", m.cells},
                             {"rows", b.weights.size()},
                             {"modes", b.modes.cols()},
                             {"energy_kept", b.keptEnergy()},
                             {"energy_target", o->energy},
                             {"orthonormality_error", b.orthonormalityError()},
                             {"spectrum_head", spectrum},
                             {"working_set_bytes", b.peakBytes},
                             {"peak_rss_bytes", peakRssBytes()},
                             {"wall_seconds", wall}};
            if (!warn.empty()) j["warning"] = warn;
            if (o->json) {
                std::cout << j.dump(2) << '\n';
                return 0;
            }
            std::cout << "POD " << j["file"].get<std::string>() << ": " << b.modes.cols() << " modes of "
                      << b.snapshots << " snapshots (" << set.files().size() << " files, " << m.cells << " cells, fields";
            for (const auto& f : m.fields) std::cout << ' ' << f;
            std::cout << ")\n  energy kept " << std::setprecision(8) << b.keptEnergy() << " (target " << o->energy
                      << "), modes orthonormal to " << std::setprecision(2) << b.orthonormalityError()
                      << "\n  working set " << std::setprecision(3) << b.peakBytes / 1e6 << " MB, peak RSS "
                      << peakRssBytes() / 1e6 << " MB, " << wall << " s\n  spectrum: "
                      << j["spectrum_png"].get<std::string>() << '\n';
            if (!warn.empty()) std::cout << "  warning: " << warn << '\n';
            return 0;
        };
    });

    auto* deim = cmd->add_subcommand(
        "deim", "Hyper-reduction of the mu(I) viscosity: DEIM on the viscosity of stored snapshots (their U and p), "
                "trained on every other time, errors on all");
    deim->add_option("FILES", o->files, "Snapshot files with U, p and boundary values (schema 2)");
    deim->add_option("--campaign", o->campaign, "Use the snapshot files of this campaign's finished runs instead");
    deim->add_option("--dir", o->dir, "Campaign directory (with --campaign)")->capture_default_str();
    deim->add_option("--modes", o->deimModes, "Largest number of DEIM points (= viscosity POD modes)")->capture_default_str();
    deim->add_flag("--log", o->logSpace, "Interpolate log(nu) instead of nu");
    deim->add_option("--plot", o->plot, "Also draw the errors against the number of points (PNG)");
    deim->add_flag("--json", o->json, "Print JSON");
    deim->callback([&action, o] {
        action = [o] {
            rom::ViscosityDeimOptions opt;
            opt.modes = o->deimModes;
            opt.logSpace = o->logSpace;
            const store::SnapshotSet set(snapshotFiles(*o));
            auto j = rom::viscosityDeim(set, opt);
            if (!o->plot.empty()) {
                const std::string warn = plotDeim(j, o->plot);
                if (!warn.empty()) j["warning"] = warn;
            }
            if (o->json) {
                std::cout << j.dump(2) << '\n';
                return 0;
            }
            std::cout << "DEIM of the mu(I) viscosity" << (o->logSpace ? " (log nu)" : "") << ": " << j["cells"]
                      << " cells, " << j["train_snapshots"] << " training and " << j["holdout_snapshots"]
                      << " held-out snapshots; relative L2 error of nu (mean / max)\n  points  training          hold-out\n";
            for (const auto& r : j["by_modes"]) {
                std::cout << "  " << std::setw(6) << r["modes"].get<int>() << "  " << std::setprecision(3) << std::setw(8)
                          << r["train"]["mean"].get<double>() << " / " << std::setw(8) << r["train"]["max"].get<double>();
                if (!r["holdout"].is_null())
                    std::cout << "  " << std::setw(8) << r["holdout"]["mean"].get<double>() << " / " << std::setw(8)
                              << r["holdout"]["max"].get<double>();
                std::cout << '\n';
            }
            return 0;
        };
    });

    // The POD-Galerkin collapse: build (bases from training runs, to a model file), check (against
    // stored runs), run (a prediction at new mu(I) coefficients).
    struct RunOptions {
        std::string pressure = "lithostatic", plot;
        rom::CollapseGalerkinOptions opt;
        bool json = false;
        void add(CLI::App* c, bool diagnoses) {
            c->add_option("--pressure", pressure, "Pressure for the mu(I) law: lithostatic | recovered (from the reduced momentum)")
                ->capture_default_str();
            c->add_option("--courant", opt.courant, "Transport Courant number of a step")->capture_default_str();
            c->add_option("--max-step-tstar", opt.maxStepTstar, "Largest step, in t* (the transport's Courant limit may set a smaller one)")
                ->capture_default_str();
            c->add_option("--c-alpha", opt.cAlpha, "Interface compression of the alpha transport (0: none)")->capture_default_str();
            c->add_option("--rtol", opt.rtol, "CVODE relative tolerance")->capture_default_str();
            c->add_flag("--restart-each-step", opt.restartEachStep, "Restart CVODE after every alpha step (the strict splitting; slower)");
            c->add_option("--mass-tolerance", opt.massTolerance, "Stop with an error when the powder volume drifts by more than this share")
                ->capture_default_str();
            if (diagnoses) {
                c->add_flag("--stored-pressure", opt.storedPressure,
                            "Diagnosis: the mu(I) law reads the run's stored pressure instead of the closure");
                c->add_flag("--stored-flux", opt.storedFlux,
                            "Diagnosis: alpha is carried by the run's stored flux (no reduced flow): the transport's own error");
            }
            c->add_flag("--json", json, "Print JSON");
        }
        // The model's build options with these run options over them.
        rom::CollapseGalerkin apply(rom::CollapseGalerkin m) const {
            if (!(opt.courant > 0 && opt.courant <= 0.5))
                throw InputError("courant", std::to_string(opt.courant), "(0, 0.5]: the van Leer transport's bound");
            if (pressure != "recovered" && pressure != "lithostatic") throw InputError("pressure", pressure, "lithostatic or recovered");
            if (!(opt.cAlpha >= 0 && opt.cAlpha <= 4)) throw InputError("c-alpha", std::to_string(opt.cAlpha), "[0, 4]");
            if (!(opt.rtol > 0 && opt.rtol < 1)) throw InputError("rtol", std::to_string(opt.rtol), "(0, 1)");
            if (!(opt.maxStepTstar > 0 && opt.maxStepTstar <= 1))
                throw InputError("max-step-tstar", std::to_string(opt.maxStepTstar), "(0, 1]");
            if (!(opt.massTolerance > 0 && opt.massTolerance <= 1))
                throw InputError("mass-tolerance", std::to_string(opt.massTolerance), "(0, 1]");
            auto& o = m.options;
            o.pressure = pressure == "recovered" ? rom::PressureClosure::recovered : rom::PressureClosure::lithostatic;
            o.courant = opt.courant;
            o.maxStepTstar = opt.maxStepTstar;
            o.cAlpha = opt.cAlpha;
            o.rtol = opt.rtol;
            o.restartEachStep = opt.restartEachStep;
            o.massTolerance = opt.massTolerance;
            o.storedPressure = opt.storedPressure;
            o.storedFlux = opt.storedFlux;
            return m;
        }
    };

    struct BuildCmd {
        std::vector<std::string> files;
        std::string output;
        rom::CollapseGalerkinOptions opt;
        std::string hyper = "ecsw";
        bool json = false;
    };
    auto bo = std::make_shared<BuildCmd>();
    auto* build = cmd->add_subcommand(
        "build", "POD-Galerkin model of the collapse from runs' snapshots on one mesh (alpha, U, p, phi), to a model file");
    build->add_option("FILES", bo->files, "Training snapshot files (snapshots export RUN -o F.h5 --fields alpha,U,p,phi --float64)")
        ->required();
    build->add_option("-o,--output", bo->output, "Model file (.h5)")->required();
    build->add_option("--modes", bo->opt.modes, "Flow modes (0: as many as --energy needs)")->capture_default_str();
    build->add_option("--energy", bo->opt.energy, "Share of the flow's energy the modes keep (with --modes 0)")->capture_default_str();
    build->add_flag("--reduced-alpha", bo->opt.reducedAlpha, "Reduce the powder fraction too (else it is carried on the mesh)");
    build->add_option("--alpha-modes", bo->opt.alphaModes, "Powder-fraction modes (0: by --alpha-energy)")->capture_default_str();
    build->add_option("--alpha-energy", bo->opt.alphaEnergy, "Share of alpha's energy its modes keep")->capture_default_str();
    build->add_option("--train-every", bo->opt.trainEvery, "Train on every k-th stored time; the others are held out")->capture_default_str();
    build->add_option("--hyper-points", bo->opt.hyperPoints,
                      "Hyper-reduce the mu(I) viscous term: evaluate the law at (at most) this many cells (0: the term on the whole mesh)")
        ->capture_default_str();
    build->add_option("--hyper", bo->hyper, "How: ecsw (positive cubature weights) | deim (interpolated viscosity)")
        ->capture_default_str();
    build->add_flag("--hyper-convection", bo->opt.hyperConvection, "Hyper-reduce the convection too (ecsw, same cap and tolerance)");
    build->add_option("--hyper-tolerance", bo->opt.hyperTolerance,
                      "ecsw: stop adding cells once the term's error on the training snapshots is this small")
        ->capture_default_str();
    build->add_flag("--json", bo->json, "Print JSON");
    build->callback([&action, bo] {
        action = [bo] {
            if (!(bo->opt.energy > 0 && bo->opt.energy <= 1)) throw InputError("energy", std::to_string(bo->opt.energy), "(0, 1]");
            if (!(bo->opt.alphaEnergy > 0 && bo->opt.alphaEnergy <= 1))
                throw InputError("alpha-energy", std::to_string(bo->opt.alphaEnergy), "(0, 1]");
            if (bo->hyper != "ecsw" && bo->hyper != "deim") throw InputError("hyper", bo->hyper, "ecsw or deim");
            bo->opt.hyperMethod = bo->hyper == "deim" ? rom::HyperMethod::deim : rom::HyperMethod::ecsw;
            std::vector<store::SnapshotFile> train;
            for (const auto& f : bo->files) train.emplace_back(f);
            const auto model = rom::CollapseGalerkin::build(train, bo->opt);
            rom::writeCollapseModel(model, train.front(), bo->output);
            const nlohmann::json j{{"model", fs::absolute(bo->output).string()},
                                   {"cells", model.mesh.cells},
                                   {"modes", model.modes()},
                                   {"flow_energy_kept", model.flow.keptEnergy()},
                                   {"alpha", model.alpha ? "reduced" : "mesh"},
                                   {"alpha_modes", model.alpha ? model.alpha->modes.cols() : 0},
                                   {"hyper", model.hyper ? bo->hyper : "none"},
                                   {"hyper_points", model.hyper ? model.hyper->size() : 0},
                                   {"hyper_training_error", model.hyper ? nlohmann::json(model.hyper->trainingError) : nlohmann::json()},
                                   {"hyper_convection_points", model.convectionHyper ? model.convectionHyper->size() : 0},
                                   {"hyper_convection_training_error",
                                    model.convectionHyper ? nlohmann::json(model.convectionHyper->trainingError) : nlohmann::json()},
                                   {"train_files", model.trainFiles.size()},
                                   {"train_times", model.trainTimes},
                                   {"build_seconds", model.buildSeconds},
                                   {"bytes", fs::file_size(bo->output)}};
            if (bo->json) {
                std::cout << j.dump(2) << '\n';
                return 0;
            }
            std::cout << std::setprecision(4) << "POD-Galerkin collapse model " << j["model"].get<std::string>() << ": "
                      << model.mesh.cells << " cells, " << model.modes() << " flow modes (energy " << model.flow.keptEnergy()
                      << "), alpha "
                      << (model.alpha ? "reduced (" + std::to_string(model.alpha->modes.cols()) + " modes)" : std::string("on the mesh"))
                      << ", mu(I) term "
                      << (model.hyper ? "at " + std::to_string(model.hyper->size()) + " cells (" + bo->hyper + ", error " +
                                            std::to_string(model.hyper->trainingError) + " on the training snapshots)"
                                      : std::string("on the mesh"))
                      << ", " << model.trainTimes << " snapshots of " << model.trainFiles.size() << " run(s), built in "
                      << model.buildSeconds << " s, " << j["bytes"].get<double>() / 1e6 << " MB\n";
            return 0;
        };
    });

    struct CheckCmd : RunOptions {
        std::string model;
        std::vector<std::string> runs;
    };
    auto co = std::make_shared<CheckCmd>();
    auto* check = cmd->add_subcommand(
        "check", "Run a collapse model from rest with each stored run's mu(I) coefficients and compare with its fields: "
                 "a reproduction for training runs, a prediction for the others");
    check->add_option("MODEL", co->model, "Model file (mixload rom build)")->required();
    check->add_option("RUNS", co->runs, "Snapshot files of runs on the model's mesh")->required();
    co->add(check, true);
    check->add_option("--plot", co->plot, "Also draw L*(t) and H*(t) of the model against each run (PNG)");
    check->callback([&action, co] {
        action = [co] {
            const auto model = co->apply(rom::readCollapseModel(co->model));
            nlohmann::json checks = nlohmann::json::array();
            for (const auto& c : co->runs) checks.push_back(rom::checkCollapse(model, store::SnapshotFile(c)));
            std::string warn;
            if (!co->plot.empty()) warn = plotGalerkin(checks, model.tStar, co->plot);
            if (!warn.empty())
                for (auto& c : checks) c["warning"] = warn;
            if (co->json) {
                std::cout << (checks.size() == 1 ? checks[0] : checks).dump(2) << '\n';
                return 0;
            }
            std::cout << std::setprecision(4);
            for (const auto& j : checks) {
                std::cout << (j["trained_on_this_run"].get<bool>() ? "reproducing " : "predicting ") << j["snapshots"].get<std::string>()
                          << " (mu_s " << j["mu_s"].get<double>() << ", mu_d " << j["mu_d"].get<double>() << ", I0 "
                          << j["i0"].get<double>() << ") with " << j["modes"] << " modes\n  pressure ("
                          << j["pressure"].get<std::string>() << ") error in the powder " << j["pressure_error_mean"].get<double>()
                          << " (lithostatic on the stored fields: " << j["lithostatic_pressure_error"].get<double>()
                          << ")\n  alpha rel. L2 error mean " << j["alpha_error_mean"].get<double>() << " max "
                          << j["alpha_error_max"].get<double>() << "; U error (of peak |U|) mean " << j["u_error_mean"].get<double>()
                          << " max " << j["u_error_max"].get<double>() << "\n  L*f " << j["runout_star"].get<double>() << " (full "
                          << j["runout_star_full"].get<double>() << ", " << 100 * j["runout_error"].get<double>() << "%), H*f "
                          << j["height_star"].get<double>() << " (full " << j["height_star_full"].get<double>() << ", "
                          << 100 * j["height_error"].get<double>() << "%)\n  online " << j["online_seconds"].get<double>()
                          << " s (" << j["steps"] << " steps, " << j["rhs_evaluations"] << " flow evaluations)\n";
            }
            if (!co->plot.empty()) std::cout << (warn.empty() ? "plot: " + co->plot : "warning: " + warn) << '\n';
            return 0;
        };
    });

    struct RunCmd : RunOptions {
        std::string model;
        double muS = 0, muD = 0, i0 = 0, endTstar = 8;
        int perTstar = 20;
        std::string fields;
        bool extrapolate = false;
    };
    auto ro = std::make_shared<RunCmd>();
    auto* run = cmd->add_subcommand("run", "Predict a collapse with a model file: L*(t), H*(t), L*f and H*f at new mu(I) coefficients "
                                    "(the mixer's M and fields at a new point: rom regression --campaign NAME --at NAME=VALUE "
                                    "... --fields OUT.h5)");
    run->add_option("MODEL", ro->model, "Model file (mixload rom build)")->required();
    run->add_option("--mu-s", ro->muS, "mu_s (as the solver reads it: the standard convention)")->required();
    run->add_option("--mu-d", ro->muD, "mu_d (> mu_s)")->required();
    run->add_option("--i0", ro->i0, "I0")->required();
    run->add_option("--end-tstar", ro->endTstar, "Simulated time, in t*")->capture_default_str();
    run->add_option("--writes-per-tstar", ro->perTstar, "Output times per t*")->capture_default_str();
    run->add_option("--fields", ro->fields, "Also write the model's alpha and U at the output times to this snapshot file (.h5, with .xmf)");
    run->add_flag("--extrapolate", ro->extrapolate,
                  "Answer even far outside the training runs' coefficients (by default refused beyond a quarter of their range)");
    ro->add(run, false);
    run->callback([&action, ro] {
        action = [ro] {
            const auto model = ro->apply(rom::readCollapseModel(ro->model));
            if (!ro->extrapolate && ro->muD > ro->muS) rom::requireNearTraining(model, ro->muS, ro->muD, ro->i0);
            rom::CollapseTrajectory tr;
            auto j = rom::predictCollapse(model, ro->muS, ro->muD, ro->i0, ro->endTstar, ro->perTstar, &tr);
            if (!ro->fields.empty()) {
                rom::writeCollapseFields(model, ro->model, tr, ro->fields);
                j["fields"] = fs::absolute(ro->fields).string();
            }
            if (ro->json) {
                std::cout << j.dump(2) << '\n';
                return 0;
            }
            std::cout << std::setprecision(4) << "collapse (mu_s " << ro->muS << ", mu_d " << ro->muD << ", I0 " << ro->i0
                      << ") by the model " << ro->model << ": L*f " << j["runout_star"].get<double>() << ", H*f "
                      << j["height_star"].get<double>() << " at " << ro->endTstar << " t* (" << j["online_seconds"].get<double>()
                      << " s)\n";
            if (j.contains("fields")) std::cout << "  fields: " << j["fields"].get<std::string>() << " (+ .xmf)\n";
            return 0;
        };
    });

    struct RegressionCmd {
        std::string campaign, dir = "runs/campaigns", fields, holdout, holdoutDir, field = "alpha";
        std::vector<std::string> at;
        rom::RegressionCheckOptions opt;
        bool json = false;
    };
    auto rg = std::make_shared<RegressionCmd>();
    rg->opt.mixerInputs = experiments::mixerInputs;
    auto* reg = cmd->add_subcommand(
        "regression", "POD regression of a campaign's final powder fraction against its inputs, left out one run at a "
                      "time, beside kriging of the campaign's quantity (M, or L*f and H*f)");
    reg->add_option("--campaign", rg->campaign, "Campaign whose finished runs kept snapshots (campaign run --snapshots)")->required();
    reg->add_option("--dir", rg->dir, "Campaign directory")->capture_default_str();
    reg->add_option("--modes", rg->opt.modes, "POD modes of the field (0: by --energy)")->capture_default_str();
    reg->add_option("--energy", rg->opt.energy, "Share of the field's fluctuation energy the modes keep")->capture_default_str();
    reg->add_option("--field", rg->field,
                    "Regress the powder fraction as is (alpha) or its logarithm (log: ln(alpha + floor); the loadings span "
                    "two decades)")
        ->check(CLI::IsMember({"alpha", "log"}))
        ->capture_default_str();
    reg->add_option("--log-floor", rg->opt.logFloor, "With --field log: the floor added to alpha (air cells stay finite)")
        ->capture_default_str();
    reg->add_option("--at", rg->at, "Instead of the leave-one-out check: predict at NAME=VALUE (one per varying input; repeatable)");
    reg->add_option("--fields", rg->fields, "With --at: write the predicted alpha (and U) to this snapshot file (.h5, with .xmf)");
    reg->add_option("--holdout", rg->holdout,
                    "Instead of the leave-one-out check: fit on every run and check on this campaign's runs (same mesh)");
    reg->add_option("--holdout-dir", rg->holdoutDir, "Where the hold-out campaign lives (default: --dir)");
    reg->add_flag("--json", rg->json, "Print JSON");
    reg->callback([&action, rg] {
        action = [rg] {
            if (rg->opt.modes < 0) throw InputError("modes", std::to_string(rg->opt.modes), "0 (by energy) or more");
            if (!(rg->opt.energy > 0 && rg->opt.energy <= 1)) throw InputError("energy", std::to_string(rg->opt.energy), "(0, 1]");
            if (!(rg->opt.logFloor > 0 && rg->opt.logFloor <= 0.1))
                throw InputError("log-floor", std::to_string(rg->opt.logFloor), "(0, 0.1]");
            rg->opt.logField = rg->field == "log";
            const auto noise = experiments::campaignNoise({rg->campaign, rg->dir})["run_noise"];
            rg->opt.surrogateNoise = noise.is_number() ? noise.get<double>() : 0.0;
            const fs::path ledger = fs::path(rg->dir) / rg->campaign / "ledger.sqlite";
            if (!rg->at.empty()) {
                if (!rg->holdout.empty()) throw InputError("holdout", rg->holdout, "without --at");
                std::map<std::string, double> point;
                for (const auto& a : rg->at) {
                    const auto eq = a.find('=');
                    const auto v = eq == std::string::npos ? std::nullopt : parseNumber(a.substr(eq + 1));
                    if (!v) throw InputError("at", a, "NAME=VALUE, e.g. rho=400");
                    point[a.substr(0, eq)] = *v;
                }
                const auto j = rom::campaignRegressionPredict(ledger, rg->campaign, rg->opt, point, rg->fields);
                if (rg->json) {
                    std::cout << j.dump(2) << '\n';
                    return 0;
                }
                for (const auto& w : j["warnings"]) std::cerr << "mixload: warning: " << w.get<std::string>() << '\n';
                std::cout << std::setprecision(4) << "POD regression of " << rg->campaign << " at " << j["at"].dump() << ":";
                for (const char* q : {"loading_kg", "runout_star", "height_star"})
                    if (j.contains(q)) std::cout << ' ' << q << " = " << j[q].get<double>();
                std::cout << " (" << j["modes"] << " modes, " << j["runs"] << " runs)\n";
                if (j.contains("fields")) std::cout << "  fields: " << j["fields"].get<std::string>() << " (+ .xmf)\n";
                return 0;
            }
            if (!rg->fields.empty()) throw InputError("fields", rg->fields, "used with --at");
            const auto j = rg->holdout.empty()
                               ? rom::campaignRegressionCheck(ledger, rg->campaign, rg->opt)
                               : rom::campaignRegressionHoldout(
                                     ledger, rg->campaign,
                                     fs::path(rg->holdoutDir.empty() ? rg->dir : rg->holdoutDir) / rg->holdout / "ledger.sqlite",
                                     rg->holdout, rg->opt);
            if (rg->json) {
                std::cout << j.dump(2) << '\n';
                return 0;
            }
            std::cout << std::setprecision(3) << "POD regression of " << j["campaign"].get<std::string>() << " ("
                      << j["scene"].get<std::string>() << ", " << j["runs"] << " runs, " << j["cells"] << " cells, inputs "
                      << j["inputs"].dump() << ", field " << j["regressed_field"].get<std::string>() << "), "
                      << (rg->holdout.empty() ? std::string("each run left out in turn")
                                              : "checked on the " + std::to_string(j["holdout_runs"].get<int>()) + " runs of " + rg->holdout)
                      << "\n  final alpha error mean "
                      << j["alpha_error_mean"].get<double>() << " (the modes' own, projection: " << j["alpha_projection_error_mean"].get<double>()
                      << ")";
            if (!j["u_error_mean"].is_null()) {
                std::cout << ", final U error mean " << j["u_error_mean"].get<double>() << " (projection "
                          << j["u_projection_error_mean"].get<double>() << ")";
                if (j["velocity"] != "every run") std::cout << " (" << j["velocity"].get<std::string>() << ")";
            } else {
                std::cout << " (U: " << j["velocity"].get<std::string>() << ")";
            }
            std::cout << ", " << 1e3 * j["predict_seconds"].get<double>() << " ms per prediction\n";
            if (j["window_mean_runs"].get<int>() > 0)
                std::cout << "  on the " << j["window_mean_runs"] << " runs whose final window is stored: the final alpha lies "
                          << j["alpha_fluctuation_mean"].get<double>() << " from the window's mean alpha (the flow's own fluctuation), "
                          << "the prediction " << j["alpha_error_to_window_mean_mean"].get<double>() << "\n";
            for (const auto& [q, s] : j["summary"].items())
                std::cout << "  " << q << ": mean |error| POD regression " << 100 * s["pod_regression_mean_abs_error"].get<double>()
                          << "% (max " << 100 * s["pod_regression_max_abs_error"].get<double>() << "%), kriging "
                          << 100 * s["kriging_mean_abs_error"].get<double>() << "% (max "
                          << 100 * s["kriging_max_abs_error"].get<double>() << "%) (the stored field itself "
                          << 100 * s["stored_field_mean_abs_error"].get<double>() << "%)\n";
            for (const auto& [q, s] : j["summary"].items())
                if (s.contains("pod_minus_kriging_ci90"))
                    std::cout << "  " << q << ": POD regression minus kriging, paired, " << 100 * s["pod_minus_kriging_mean_abs_error"].get<double>()
                              << " points (90% bootstrap interval " << 100 * s["pod_minus_kriging_ci90"][0].get<double>() << " .. "
                              << 100 * s["pod_minus_kriging_ci90"][1].get<double>() << ")\n";
            if (const auto& l = j["summary"].value("loading_kg", nlohmann::json::object()); l.contains("steady_model_mean_abs_error"))
                std::cout << "  loading_kg: mean |error| steady transport model " << 100 * l["steady_model_mean_abs_error"].get<double>()
                          << "% (max " << 100 * l["steady_model_max_abs_error"].get<double>() << "%; on the runs' own U "
                          << 100 * l["steady_model_on_run_u_mean_abs_error"].get<double>() << "%), "
                          << l["steady_model_seconds"].get<double>() << " s per prediction\n";
            return 0;
        };
    });

    // The mixer's steady powder transport on a run's own fields: what a reduced steady model
    // would hold with the run's flux, or with the flux rebuilt from its velocity.
    struct SteadyCmd {
        std::string file;
        rom::SteadyCheckOptions opt;
        bool json = false;
    };
    auto st = std::make_shared<SteadyCmd>();
    auto* steady = cmd->add_subcommand(
        "steady", "A mixer run's loading beside the loading its flow would hold at steady state (steady upwind powder "
                  "transport from the inlet), from the solver's flux phi and from the flux rebuilt from U");
    steady->add_option("FILE", st->file, "Mixer snapshots (snapshots export RUN -o F.h5 --fields alpha,U,phi)")->required();
    steady->add_option("--every", st->opt.every, "Every k-th stored time (the last always)")->capture_default_str();
    steady->add_option("--mean-last", st->opt.meanLast, "Also the steady transport of phi averaged over the last K stored times")
        ->capture_default_str();
    steady->add_option("--march", st->opt.marchSeconds,
                       "Also march alpha from the last stored state for this many seconds on that mean flux (explicit, "
                       "compressive, as the solver)")
        ->capture_default_str();
    steady->add_option("--c-alpha", st->opt.cAlpha, "The march's interface compression")->capture_default_str();
    steady->add_flag("--json", st->json, "Print JSON");
    steady->callback([&action, st] {
        action = [st] {
            const store::SnapshotFile f(st->file);
            const auto j = rom::steadyLoadingCheck(f, st->opt);
            if (st->json) {
                std::cout << j.dump(2) << '\n';
                return 0;
            }
            std::cout << "Steady powder transport on " << st->file << " (" << j["cells"] << " cells, "
                      << std::setprecision(3) << j["seconds_per_steady_solve"].get<double>() << " s per solve)\n"
                      << "  time (s)  loading (kg)  steady from phi (kg)  steady from U (kg)  flux error of U\n";
            const auto cell = [](const nlohmann::json& r, const char* k, int w) {
                std::ostringstream os;
                if (r.contains(k)) os << std::setprecision(4) << r[k].get<double>();
                else os << "-";
                return std::string(static_cast<size_t>(std::max(0, w - static_cast<int>(os.str().size()))), ' ') + os.str();
            };
            for (const auto& r : j["times"])
                std::cout << cell(r, "time_s", 10) << cell(r, "loading_kg", 14) << cell(r, "steady_from_phi_kg", 22)
                          << cell(r, "steady_from_u_kg", 20) << cell(r, "flux_error_u", 17) << '\n';
            if (j.contains("mean_flux")) {
                const auto& mf = j["mean_flux"];
                std::cout << "  phi averaged over the last " << mf["times"] << " times (" << mf["from_s"].get<double>() << " to "
                          << mf["to_s"].get<double>() << " s): the run holds " << std::setprecision(4)
                          << mf["loading_kg"].get<double>() << " kg, its steady transport " << mf["steady_kg"].get<double>() << " kg\n";
            }
            if (j.contains("march")) {
                const auto& mr = j["march"];
                std::cout << "  alpha marched on that flux (cAlpha " << mr["c_alpha"].get<double>() << ", " << mr["steps"] << " steps, "
                          << std::setprecision(3) << mr["wall_seconds"].get<double>() << " s):";
                for (const auto& h : mr["history"])
                    std::cout << ' ' << std::setprecision(3) << h["time_s"].get<double>() << " s " << std::setprecision(4)
                              << h["loading_kg"].get<double>() << " kg;";
                std::cout << '\n';
            }
            return 0;
        };
    });
}

}  // namespace mixload::app
