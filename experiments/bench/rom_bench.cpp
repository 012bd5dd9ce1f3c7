// SPDX-License-Identifier: GPL-3.0-or-later
#include "bench/rom_bench.hpp"

#include "bench/pareto.hpp"

#include <optional>
#include <algorithm>
#include <chrono>
#include <functional>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/clock.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "common/stats.hpp"
#include "kriging/kriging.hpp"
#include "kriging/unit_box.hpp"
#include "post/snapshots.hpp"
#include "rom/galerkin/collapse_check.hpp"
#include "rom/regression/pod_regression.hpp"
#include "run/collapse_job.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

struct FullRun {
    CollapsePoint point;
    nlohmann::json result;
    fs::path snapshots;
    double exportSeconds = 0;
};

// A full run with the writes a reduced model needs, and its float64 snapshots with the flux.
// The base collapse at a point's coefficients, on the base mesh or another.
run::CollapseJob jobAt(const RomBench& b, const CollapsePoint& p, const std::string& name, int cells, int writesPerTstar) {
    scene::CollapseOverrides o = b.base;
    o.muS = p.muS;
    o.muD = p.muD;
    o.I0 = p.i0;
    o.cellsPerLength = cells;
    o.writesPerTstar = writesPerTstar;
    run::CollapseJob job;
    job.scene = o.scene();
    job.out = b.out / "runs" / name;
    return job;
}

FullRun fullRun(const RomBench& b, const CollapsePoint& p, const std::string& name) {
    const auto job = jobAt(b, p, name, b.base.cellsPerLength, 20);
    FullRun r{p, run::runCollapse(job), job.out / "snapshots.h5", 0};
    if (!fs::exists(r.snapshots)) {
        const auto t0 = Clock::now();
        post::SnapshotExport e;
        e.runDir = job.out;
        e.output = r.snapshots;
        e.fields = {"alpha", "U", "p", "phi"};
        e.float64 = true;
        post::exportSnapshots(e);
        r.exportSeconds = secondsSince(t0);
    }
    return r;
}

std::string label(const CollapsePoint& p) {
    std::ostringstream os;
    os << std::setprecision(4) << "(" << p.muS << ", " << p.muD << ", " << p.i0 << ")";
    return os.str();
}

// One held-out point on a coarser mesh: the full model's cheap answer (no snapshots).
nlohmann::json coarseRun(const RomBench& b, const CollapsePoint& p, int cells, const std::string& name) {
    return run::runCollapse(jobAt(b, p, name, cells, b.base.writesPerTstar));
}

}  // namespace

nlohmann::json runRomBench(const RomBench& b) {
    if (b.train.size() < 2) throw InputError("train", std::to_string(b.train.size()) + " points", "two or more training points");
    if (b.heldOut.empty()) throw InputError("held-out", "none", "one or more held-out points");
    for (int n : b.coarseCells)
        if (n >= b.base.cellsPerLength)
            throw InputError("coarse-meshes", std::to_string(n),
                             "fewer cells per length than the reference mesh's " + std::to_string(b.base.cellsPerLength));
    fs::create_directories(b.out);
    const auto say = [&](const std::string& s) {
        if (b.progress) std::cerr << "bench pareto: " << s << '\n';
    };

    // Full runs: training (offline) and held out (the reference and the full model's own cost).
    std::vector<FullRun> train, held;
    double offlineFull = 0, offlineExport = 0;
    for (size_t i = 0; i < b.train.size(); ++i) {
        say("training run " + std::to_string(i + 1) + " of " + std::to_string(b.train.size()) + " " + label(b.train[i]));
        train.push_back(fullRun(b, b.train[i], "train-" + std::to_string(i)));
        offlineFull += train.back().result["wall_seconds"].get<double>();
        offlineExport += train.back().exportSeconds;
    }
    for (size_t i = 0; i < b.heldOut.size(); ++i) {
        say("held-out run " + std::to_string(i + 1) + " of " + std::to_string(b.heldOut.size()) + " " + label(b.heldOut[i]));
        held.push_back(fullRun(b, b.heldOut[i], "held-" + std::to_string(i)));
    }

    // The Galerkin model.
    say("building the POD-Galerkin model");
    std::vector<store::SnapshotFile> files;
    for (const auto& r : train) files.emplace_back(r.snapshots);
    const auto model = rom::CollapseGalerkin::build(files, b.options);
    std::optional<rom::CollapseGalerkin> hyperModel;
    if (b.hyperTolerance > 0) {
        say("building the hyper-reduced POD-Galerkin model");
        auto o = b.options;
        o.hyperMethod = rom::HyperMethod::ecsw;
        o.hyperConvection = true;
        o.hyperTolerance = b.hyperTolerance;
        o.hyperPoints = static_cast<int>(model.mesh.cells);
        hyperModel = rom::CollapseGalerkin::build(files, o);
    }

    // Kriging on L*f and H*f over (mu_s, mu_d, I0), inputs scaled to the training box.
    const auto nT = static_cast<Eigen::Index>(train.size());
    Eigen::MatrixXd Xraw(nT, 3);
    Eigen::VectorXd yL(nT), yH(nT);
    const auto raw = [](const CollapsePoint& p) { return Eigen::VectorXd(Eigen::Vector3d(p.muS, p.muD, p.i0)); };
    for (Eigen::Index i = 0; i < nT; ++i) {
        Xraw.row(i) = raw(train[static_cast<size_t>(i)].point).transpose();
        yL[i] = train[static_cast<size_t>(i)].result["runout_star"].get<double>();
        yH[i] = train[static_cast<size_t>(i)].result["height_star"].get<double>();
    }
    const auto box = surrogates::UnitBox::of(Xraw);
    auto t0 = Clock::now();
    surrogates::KrigingOptions ko;
    const auto kL = surrogates::Kriging::fit(box.rows(Xraw), yL, ko), kH = surrogates::Kriging::fit(box.rows(Xraw), yH, ko);
    const double krigingFit = secondsSince(t0);

    // POD regression of the final deposit: the last stored alpha of each training run.
    t0 = Clock::now();
    const auto& mesh = model.mesh;
    Eigen::MatrixXd finals(mesh.cells, nT);
    for (Eigen::Index i = 0; i < nT; ++i)
        finals.col(i) = files[static_cast<size_t>(i)].column("alpha", files[static_cast<size_t>(i)].times().size() - 1);
    const auto regression = rom::PodRegression::fit(Xraw, finals, mesh.V, 0);
    const double regressionFit = secondsSince(t0);

    nlohmann::json rows = nlohmann::json::array();
    double fullMean = 0, romMean = 0, krigMean = 0, regMean = 0, hyperMean = 0;
    for (size_t h = 0; h < held.size(); ++h) {
        const auto& r = held[h];
        say("predicting " + label(r.point));
        const store::SnapshotFile f(r.snapshots);
        const auto c = rom::checkCollapse(model, f);
        auto ws = kL.makeWorkspace();
        const Eigen::VectorXd x = box(raw(r.point));
        // Many calls: one is far below the clock's resolution.
        t0 = Clock::now();
        double L = 0, H = 0;
        const int reps = 10000;
        for (int k = 0; k < reps; ++k) {
            L = kL.predictMean(x.data(), ws);
            H = kH.predictMean(x.data(), ws);
        }
        const double krigSeconds = secondsSince(t0) / reps;
        const double Lf = r.result["runout_star"], Hf = r.result["height_star"];
        t0 = Clock::now();
        Eigen::VectorXd alphaReg;
        double Lreg = 0, Hreg = 0;
        const int regReps = 100;
        for (int k = 0; k < regReps; ++k) {
            alphaReg = regression.predict(raw(r.point));
            Lreg = model.shape.runoutStar(mesh, alphaReg);
            Hreg = model.shape.heightStar(mesh, alphaReg);
        }
        const double regSeconds = secondsSince(t0) / regReps;
        const Eigen::VectorXd alphaFinal = f.column("alpha", f.times().size() - 1);
        const double regAlphaError = std::sqrt((alphaReg - alphaFinal).cwiseAbs2().dot(mesh.V) / alphaFinal.cwiseAbs2().dot(mesh.V));
        regMean += regSeconds / static_cast<double>(held.size());
        const double full = r.result["wall_seconds"];
        fullMean += full / static_cast<double>(held.size());
        romMean += c["online_seconds"].get<double>() / static_cast<double>(held.size());
        krigMean += krigSeconds / static_cast<double>(held.size());
        // A Galerkin model's check of this run as the table's entry (both models, one shape).
        const auto galerkinRow = [&](const nlohmann::json& check) {
            return nlohmann::json{{"seconds", check["online_seconds"]},
                                  {"runout_star", check["runout_star"]},
                                  {"height_star", check["height_star"]},
                                  {"runout_error", (check["runout_star"].get<double>() - Lf) / Lf},
                                  {"height_error", (check["height_star"].get<double>() - Hf) / Hf},
                                  {"alpha_error", check["alpha_error_mean"]},
                                  {"u_error", check["u_error_mean"]},
                                  {"u_projection_error", check["u_projection_error_mean"]}};
        };
        rows.push_back({{"mu_s", r.point.muS},
                        {"mu_d", r.point.muD},
                        {"i0", r.point.i0},
                        {"full", {{"seconds", full}, {"runout_star", Lf}, {"height_star", Hf}}},
                        {"galerkin", galerkinRow(c)},
                        {"galerkin_hyper", nullptr},
                        {"pod_regression",
                         {{"seconds", regSeconds},
                          {"runout_star", Lreg},
                          {"height_star", Hreg},
                          {"runout_error", (Lreg - Lf) / Lf},
                          {"height_error", (Hreg - Hf) / Hf},
                          {"final_alpha_error", regAlphaError}}},
                        {"kriging",
                         {{"seconds", krigSeconds},
                          {"runout_star", L},
                          {"height_star", H},
                          {"runout_error", (L - Lf) / Lf},
                          {"height_error", (H - Hf) / Hf}}}});
        nlohmann::json coarse = nlohmann::json::array();
        for (int n : b.coarseCells) {
            say("held-out run " + label(r.point) + " on Li/" + std::to_string(n));
            const auto c = coarseRun(b, r.point, n, "held-" + std::to_string(h) + "-li" + std::to_string(n));
            coarse.push_back({{"cells_per_length", n},
                              {"seconds", c["wall_seconds"]},
                              {"runout_star", c["runout_star"]},
                              {"height_star", c["height_star"]},
                              {"runout_error", (c["runout_star"].get<double>() - Lf) / Lf},
                              {"height_error", (c["height_star"].get<double>() - Hf) / Hf}});
        }
        rows.back()["full_coarse"] = coarse;
        if (hyperModel) {
            const auto ch = rom::checkCollapse(*hyperModel, f);
            hyperMean += ch["online_seconds"].get<double>() / static_cast<double>(held.size());
            auto row = galerkinRow(ch);
            row["hyper_points"] = ch["hyper_points"];
            row["hyper_convection_points"] = ch["hyper_convection_points"];
            row["hyper_term_error"] = ch["hyper_term_error_mean"];
            rows.back()["galerkin_hyper"] = row;
        }
    }
    const double romOffline = offlineFull + offlineExport + model.buildSeconds;
    const double krigOffline = offlineFull + krigingFit;
    const auto breakEven = [&](double offline, double online) {
        return fullMean > online ? offline / (fullMean - online) : std::numeric_limits<double>::infinity();
    };
    nlohmann::json out{{"cells", model.mesh.cells},
                       {"modes", model.modes()},
                       {"alpha", model.alpha ? "reduced" : "mesh"},
                       {"pressure", b.options.pressure == rom::PressureClosure::recovered ? "recovered" : "lithostatic"},
                       {"train_runs", train.size()},
                       {"held_out_runs", held.size()},
                       {"offline",
                        {{"full_runs_seconds", offlineFull},
                         {"export_seconds", offlineExport},
                         {"galerkin_build_seconds", model.buildSeconds},
                         {"kriging_fit_seconds", krigingFit},
                         {"pod_regression_fit_seconds", regressionFit}}},
                       {"pod_regression_modes", regression.modes()},
                       {"mean_seconds", {{"full", fullMean}, {"galerkin", romMean}, {"pod_regression", regMean}, {"kriging", krigMean}}},
                       {"hyper",
                        hyperModel ? nlohmann::json{{"points", hyperModel->hyper->size()},
                                                    {"training_error", hyperModel->hyper->trainingError},
                                                    {"convection_points", hyperModel->convectionHyper->size()},
                                                    {"convection_training_error", hyperModel->convectionHyper->trainingError},
                                                    {"build_seconds", hyperModel->buildSeconds},
                                                    {"mean_seconds", hyperMean},
                                                    {"speedup", fullMean / hyperMean}}
                                   : nlohmann::json()},
                       {"speedup", {{"galerkin", fullMean / romMean}, {"pod_regression", fullMean / regMean}, {"kriging", fullMean / krigMean}}},
                       {"break_even_answers",
                        {{"galerkin", breakEven(romOffline, romMean)},
                         {"pod_regression", breakEven(offlineFull + regressionFit, regMean)},
                         {"kriging", breakEven(krigOffline, krigMean)}}},
                       {"rows", rows}};

    // Time against error: per method the medians over the held-out runs.
    std::vector<ParetoMethod> methods;
    const auto summarise = [&](const std::string& name, const std::function<const nlohmann::json&(const nlohmann::json&)>& at,
                               double offline) {
        std::vector<double> t, eL, eH;
        for (const auto& r : rows) {
            const auto& m = at(r);
            t.push_back(m["seconds"].get<double>());
            eL.push_back(std::abs(m["runout_error"].get<double>()));
            eH.push_back(std::abs(m["height_error"].get<double>()));
        }
        const double l = median(eL), h = median(eH);
        methods.push_back({name, median(t), std::max(l, h), {l, h}, offline, false, false});
    };
    {
        std::vector<double> t;
        for (const auto& r : rows) t.push_back(r["full"]["seconds"].get<double>());
        methods.push_back({"full run, Li/" + std::to_string(b.base.cellsPerLength) + " (reference)", median(t), 0, {0, 0}, 0, true, false});
    }
    for (size_t k = 0; k < b.coarseCells.size(); ++k)
        summarise("full run, Li/" + std::to_string(b.coarseCells[k]), [k](const nlohmann::json& r) -> const nlohmann::json& { return r["full_coarse"][k]; }, 0);
    summarise("POD-Galerkin", [](const nlohmann::json& r) -> const nlohmann::json& { return r["galerkin"]; }, romOffline);
    if (hyperModel)
        summarise("POD-Galerkin, hyper-reduced (ECSW)", [](const nlohmann::json& r) -> const nlohmann::json& { return r["galerkin_hyper"]; },
                  romOffline - model.buildSeconds + hyperModel->buildSeconds);
    summarise("POD regression", [](const nlohmann::json& r) -> const nlohmann::json& { return r["pod_regression"]; },
              offlineFull + regressionFit);
    summarise("kriging", [](const nlohmann::json& r) -> const nlohmann::json& { return r["kriging"]; }, krigOffline);
    const ParetoPlot plot{"Collapse, " + std::to_string(held.size()) + " held-out runs (" + std::to_string(model.mesh.cells) +
                              " cells at Li/" + std::to_string(b.base.cellsPerLength) + "), models trained on " +
                              std::to_string(train.size()) +
                              "; medians over the held-out runs; error: |relative error| against the reference full run.",
                          "Collapse: time against error, " + std::to_string(held.size()) + " held-out runs",
                          "online time per answer [s] (median)",
                          "error: larger of the median |relative errors| in L*f, H*f",
                          {"median L*f error", "median H*f error"},
                          {"runout_error", "height_error"}};
    out.update(writePareto(b.out, plot, methods));

    // Table and plot: error against online time per held-out run and method.
    std::ostringstream md, csv, dat;
    md << "| held-out (mu_s, mu_d, I0) | full L*f, H*f (s) | Galerkin L*f, H*f error (s) | Galerkin, hyper-reduced (s) | "
          "POD regression L*f, H*f error (s) | kriging L*f, H*f error (s) |\n|---|---|---|---|---|---|\n";
    csv << "mu_s,mu_d,i0,full_s,runout_full,height_full,galerkin_s,galerkin_runout_error,galerkin_height_error,galerkin_alpha_error,"
           "regression_s,regression_runout_error,regression_height_error,regression_final_alpha_error,kriging_s,kriging_runout_error,"
           "kriging_height_error,hyper_s,hyper_runout_error,hyper_height_error,hyper_alpha_error\n";
    md << std::setprecision(4);
    csv << std::setprecision(8);
    for (const auto& r : rows) {
        const auto& g = r["galerkin"];
        const auto& k = r["kriging"];
        const auto& p = r["pod_regression"];
        md << "| (" << r["mu_s"].get<double>() << ", " << r["mu_d"].get<double>() << ", " << r["i0"].get<double>() << ") | "
           << r["full"]["runout_star"].get<double>() << ", " << r["full"]["height_star"].get<double>() << " ("
           << r["full"]["seconds"].get<double>() << ") | " << 100 * g["runout_error"].get<double>() << "%, "
           << 100 * g["height_error"].get<double>() << "% (" << g["seconds"].get<double>() << ") | ";
        if (r["galerkin_hyper"].is_null()) md << "– | ";
        else
            md << 100 * r["galerkin_hyper"]["runout_error"].get<double>() << "%, " << 100 * r["galerkin_hyper"]["height_error"].get<double>()
               << "% (" << r["galerkin_hyper"]["seconds"].get<double>() << ") | ";
        md << 100 * p["runout_error"].get<double>() << "%, " << 100 * p["height_error"].get<double>() << "% ("
           << p["seconds"].get<double>() << ") | " << 100 * k["runout_error"].get<double>() << "%, " << 100 * k["height_error"].get<double>() << "% ("
           << k["seconds"].get<double>() << ") |\n";
        csv << r["mu_s"] << ',' << r["mu_d"] << ',' << r["i0"] << ',' << r["full"]["seconds"] << ',' << r["full"]["runout_star"]
            << ',' << r["full"]["height_star"] << ',' << g["seconds"] << ',' << g["runout_error"] << ',' << g["height_error"]
            << ',' << g["alpha_error"] << ',' << p["seconds"] << ',' << p["runout_error"] << ',' << p["height_error"] << ','
            << p["final_alpha_error"] << ',' << k["seconds"] << ',' << k["runout_error"] << ',' << k["height_error"];
        if (r["galerkin_hyper"].is_null()) csv << ",,,,\n";
        else {
            const auto& hy = r["galerkin_hyper"];
            csv << ',' << hy["seconds"] << ',' << hy["runout_error"] << ',' << hy["height_error"] << ',' << hy["alpha_error"] << '\n';
        }
        dat << g["seconds"].get<double>() << ' ' << std::abs(g["runout_error"].get<double>()) << ' '
            << std::abs(g["height_error"].get<double>()) << ' ' << k["seconds"].get<double>() << ' '
            << std::abs(k["runout_error"].get<double>()) << ' ' << std::abs(k["height_error"].get<double>()) << ' '
            << r["full"]["seconds"].get<double>() << ' ' << p["seconds"].get<double>() << ' '
            << std::abs(p["runout_error"].get<double>()) << ' ' << std::abs(p["height_error"].get<double>());
        if (r["galerkin_hyper"].is_null()) dat << " NaN NaN NaN\n";
        else
            dat << ' ' << r["galerkin_hyper"]["seconds"].get<double>() << ' ' << std::abs(r["galerkin_hyper"]["runout_error"].get<double>())
                << ' ' << std::abs(r["galerkin_hyper"]["height_error"].get<double>()) << '\n';
    }
    writeFileAtomic(b.out / "table.md", md.str());
    writeFileAtomic(b.out / "table.csv", csv.str());
    writeFileAtomic(b.out / "rom-bench.dat", dat.str());
    std::ostringstream gp;
    gp << "set terminal pngcairo size 800,560\nset output 'rom-bench.png'\nset logscale xy\nset grid\n"
       << "set format x '10^{%L}'\nset format y '10^{%L}'\nset xlabel 'online time per answer [s]'\n"
       << "set ylabel '|relative error| against the held-out full run'\nset key bottom left font \",9\"\n"
       << "set title 'Collapse: " << held.size() << " held-out runs, models trained on " << train.size() << "'\n"
       << "set yrange [5e-5:1]\nset arrow from graph 0, first 0.05 to graph 1, first 0.05 nohead dt 2\n"
       << "plot 'rom-bench.dat' u 1:2 w p pt 7 ps 1.3 t 'POD-Galerkin, L*f', '' u 1:3 w p pt 6 ps 1.3 t 'POD-Galerkin, H*f', "
       << "'' u 4:5 w p pt 5 ps 1.3 t 'kriging, L*f', '' u 4:6 w p pt 4 ps 1.3 t 'kriging, H*f', "
       << "'' u 8:9 w p pt 13 ps 1.3 t 'POD regression, L*f', '' u 8:10 w p pt 12 ps 1.3 t 'POD regression, H*f', "
       << "'' u 11:12 w p pt 3 ps 1.3 t 'POD-Galerkin hyper-reduced, L*f', '' u 11:13 w p pt 1 ps 1.3 t 'POD-Galerkin hyper-reduced, H*f', "
       << "'' u 7:(1e-4) w p pt 9 ps 1.5 t 'full run (reference, drawn at 1e-4)'\n";
    const std::string warn = runGnuplot(b.out, "rom-bench.gp", gp.str());
    out["table"] = (b.out / "table.md").string();
    out["plot"] = (b.out / "rom-bench.png").string();
    if (!warn.empty()) out["warning"] = warn;
    return out;
}

}  // namespace mixload::experiments
