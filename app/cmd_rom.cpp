// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload rom`: reduced-order models on stored snapshots. `rom pod` builds a POD basis.
#include <sys/resource.h>

#include <chrono>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "app/commands.hpp"
#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "rom/collapse_galerkin.hpp"
#include "rom/pod_model.hpp"
#include "rom/viscosity_deim.hpp"
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
    auto* cmd = app.add_subcommand("rom", "Reduced-order models on stored snapshots (POD; see README, Reduced models)");
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
            const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
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

    struct GalerkinCmd {
        std::vector<std::string> files, check;
        std::string pressure = "lithostatic", plot;
        rom::CollapseGalerkinOptions opt;
        bool json = false;
    };
    auto g = std::make_shared<GalerkinCmd>();
    auto* gal = cmd->add_subcommand(
        "galerkin", "POD-Galerkin model of the collapse: build it on runs' snapshots (alpha, U, p, phi), run it from "
                    "rest with each checked run's mu(I) coefficients and compare with every stored field");
    gal->add_option("FILES", g->files, "Training snapshot files of collapses on one mesh (snapshots export ... --fields alpha,U,p,phi --float64)")
        ->required();
    gal->add_option("--check", g->check, "Runs to compare with (default: the training runs); held-out runs make it a prediction");
    gal->add_option("--modes", g->opt.modes, "Flow modes (0: as many as --energy needs)")->capture_default_str();
    gal->add_option("--energy", g->opt.energy, "Share of the flow's energy the modes keep (with --modes 0)")->capture_default_str();
    gal->add_flag("--reduced-alpha", g->opt.reducedAlpha, "Reduce the powder fraction too (else it is carried on the mesh)");
    gal->add_option("--alpha-modes", g->opt.alphaModes, "Powder-fraction modes (0: by --alpha-energy)")->capture_default_str();
    gal->add_option("--alpha-energy", g->opt.alphaEnergy, "Share of alpha's energy its modes keep")->capture_default_str();
    gal->add_option("--train-every", g->opt.trainEvery, "Train on every k-th stored time; the others are held out")->capture_default_str();
    gal->add_option("--courant", g->opt.courant, "Transport Courant number of a step")->capture_default_str();
    gal->add_option("--c-alpha", g->opt.cAlpha, "Interface compression of the alpha transport (0: none)")->capture_default_str();
    gal->add_option("--rtol", g->opt.rtol, "CVODE relative tolerance")->capture_default_str();
    gal->add_flag("--restart-each-step", g->opt.restartEachStep,
                  "Restart CVODE after every alpha step (the strict splitting; slower)");
    gal->add_option("--mass-tolerance", g->opt.massTolerance,
                    "Stop with an error when the powder volume drifts by more than this share")->capture_default_str();
    gal->add_option("--pressure", g->pressure, "Pressure for the mu(I) law: recovered (from the reduced momentum) | lithostatic")
        ->capture_default_str();
    gal->add_flag("--stored-pressure", g->opt.storedPressure,
                  "Diagnosis: the mu(I) law reads the run's stored pressure instead of the lithostatic closure");
    gal->add_flag("--stored-flux", g->opt.storedFlux,
                  "Diagnosis: alpha is carried by the run's stored flux (no reduced flow): the transport's own error");
    gal->add_option("--plot", g->plot, "Also draw L*(t) and H*(t) of the model against each checked run (PNG)");
    gal->add_flag("--json", g->json, "Print JSON (with the per-time errors)");
    gal->callback([&action, g] {
        action = [g] {
            if (!(g->opt.courant > 0 && g->opt.courant <= 0.5))
                throw InputError("courant", std::to_string(g->opt.courant), "(0, 0.5]: the van Leer transport's bound");
            if (!(g->opt.energy > 0 && g->opt.energy <= 1)) throw InputError("energy", std::to_string(g->opt.energy), "(0, 1]");
            if (g->pressure != "recovered" && g->pressure != "lithostatic")
                throw InputError("pressure", g->pressure, "recovered or lithostatic");
            g->opt.pressure = g->pressure == "recovered" ? rom::PressureClosure::recovered : rom::PressureClosure::lithostatic;
            if (!(g->opt.cAlpha >= 0 && g->opt.cAlpha <= 4)) throw InputError("c-alpha", std::to_string(g->opt.cAlpha), "[0, 4]");
            if (!(g->opt.massTolerance > 0 && g->opt.massTolerance <= 1))
                throw InputError("mass-tolerance", std::to_string(g->opt.massTolerance), "(0, 1]");
            std::vector<store::SnapshotFile> train;
            for (const auto& f : g->files) train.emplace_back(f);
            std::vector<const store::SnapshotFile*> ptrs;
            for (const auto& f : train) ptrs.push_back(&f);
            const auto model = rom::CollapseGalerkin::build(ptrs, g->opt);
            nlohmann::json checks = nlohmann::json::array();
            for (const auto& c : g->check.empty() ? g->files : g->check) checks.push_back(rom::checkCollapse(model, store::SnapshotFile(c)));
            std::string warn;
            if (!g->plot.empty()) warn = plotGalerkin(checks, model.tStar, g->plot);
            if (!warn.empty())
                for (auto& c : checks) c["warning"] = warn;
            if (g->json) {
                std::cout << (checks.size() == 1 ? checks[0] : checks).dump(2) << '\n';
                return 0;
            }
            std::cout << std::setprecision(4) << "POD-Galerkin collapse on " << model.mesh.cells << " cells: " << model.modes()
                      << " flow modes (energy " << model.flow.keptEnergy() << "), alpha "
                      << (model.alpha ? "reduced (" + std::to_string(model.alpha->modes.cols()) + " modes)" : std::string("on the mesh"))
                      << ", " << model.trainTimes << " snapshots of " << model.trainFiles.size() << " run(s), built in "
                      << model.buildSeconds << " s\n";
            for (const auto& j : checks) {
            std::cout << (j["trained_on_this_run"].get<bool>() ? "reproducing " : "predicting ") << j["snapshots"].get<std::string>()
                      << " (mu_s " << j["mu_s"].get<double>() << ", mu_d " << j["mu_d"].get<double>() << ", I0 "
                      << j["i0"].get<double>() << ")\n  pressure (" << j["pressure"].get<std::string>() << ") error in the powder " << j["pressure_error_mean"].get<double>()
                      << " (lithostatic on the stored fields: " << j["lithostatic_pressure_error"].get<double>()
                      << ")\n  alpha rel. L2 error mean "
                      << j["alpha_error_mean"].get<double>() << " max " << j["alpha_error_max"].get<double>()
                      << "; U error (of peak |U|) mean " << j["u_error_mean"].get<double>() << " max "
                      << j["u_error_max"].get<double>() << "\n  L*f " << j["runout_star"].get<double>() << " (full "
                      << j["runout_star_full"].get<double>() << ", " << 100 * j["runout_error"].get<double>() << "%), H*f "
                      << j["height_star"].get<double>() << " (full " << j["height_star_full"].get<double>() << ", "
                      << 100 * j["height_error"].get<double>() << "%)\n  online " << j["online_seconds"].get<double>()
                      << " s (" << j["steps"] << " steps, " << j["rhs_evaluations"] << " flow evaluations)\n";
            }
            if (!g->plot.empty()) std::cout << (warn.empty() ? "plot: " + g->plot : "warning: " + warn) << '\n';
            return 0;
        };
    });
}

}  // namespace mixload::app
