// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload bench pareto` (also `bench rom`): time against error on held-out collapse runs for the
// full model on several meshes, the POD-Galerkin model, POD regression and kriging.
#include <iomanip>
#include <iostream>

#include "app/collapse_options.hpp"
#include "app/commands.hpp"
#include "bench/rom_bench.hpp"
#include "common/atomic_file.hpp"
#include "common/input_error.hpp"

namespace mixload::app {

namespace {
struct BenchRom {
    CollapseOptions scene;
    std::vector<std::string> train{"1.0:1.375:0.3", "0.7:0.95:0.38", "1.3:1.55:0.22", "0.7:1.2:0.22", "1.3:1.8:0.38"};
    std::vector<std::string> held{"0.85:1.2:0.33", "1.15:1.45:0.26", "0.9:1.35:0.25", "1.33:1.69:0.3"};
    int modes = 20;
    std::string pressure = "lithostatic";
    double hyperTolerance = 0.003;
    std::vector<int> coarse{5, 6};  // Li/4 loses 0.13% of the powder at a = 2: refused
    std::string out = "runs/bench-rom";
    bool json = false;
};

experiments::CollapsePoint parseCollapsePoint(const std::string& field, const std::string& text) {
    std::vector<double> v;
    std::string rest = text;
    for (size_t at; (at = rest.find(':')) != std::string::npos || !rest.empty();) {
        const auto part = at == std::string::npos ? rest : rest.substr(0, at);
        const auto x = parseNumber(part);
        if (!x) throw InputError(field, text, "mu_s:mu_d:I0, e.g. 1.0:1.375:0.3");
        v.push_back(*x);
        rest = at == std::string::npos ? "" : rest.substr(at + 1);
    }
    if (v.size() != 3) throw InputError(field, text, "mu_s:mu_d:I0, e.g. 1.0:1.375:0.3");
    return {v[0], v[1], v[2]};
}
}  // namespace

void addBenchRom(CLI::App* bench, Action& action) {
    auto o = std::make_shared<BenchRom>();
    o->scene.cellsPerLength = 8;
    auto* c = bench->add_subcommand(
        "pareto", "Collapse: time against error on held-out (mu_s, mu_d, I0) for full runs on the reference and coarser meshes, the "
                  "POD-Galerkin model, POD regression and kriging: time and error per answer, offline cost, break-even, the Pareto "
                  "front (also: bench rom)");
    c->alias("rom");
    o->scene.add(c);
    c->add_option("--train", o->train, "Training points mu_s:mu_d:I0")->capture_default_str();
    c->add_option("--held-out", o->held, "Held-out points mu_s:mu_d:I0")->capture_default_str();
    c->add_option("--coarse-meshes", o->coarse, "Coarser meshes (cells per length) the full model also runs on at the held-out points")
        ->delimiter(',')
        ->capture_default_str();
    c->add_option("--modes", o->modes, "Flow modes of the Galerkin model")->capture_default_str();
    c->add_option("--pressure", o->pressure, "Galerkin pressure closure: lithostatic | recovered")->capture_default_str();
    c->add_option("--hyper-tolerance", o->hyperTolerance,
                  "Also a Galerkin model with the mu(I) and convection terms hyper-reduced (ECSW) to this training error (0: not)")
        ->capture_default_str();
    c->add_option("--out", o->out, "Directory (full runs resume from it)")->capture_default_str();
    c->add_flag("--json", o->json, "Print JSON");
    c->callback([&action, o] {
        action = [o] {
            experiments::RomBench b;
            requireRange("hyper-tolerance", o->hyperTolerance, 0.0, 1.0, true, false);
            b.hyperTolerance = o->hyperTolerance;
            b.base = o->scene;
            for (const auto& t : o->train) b.train.push_back(parseCollapsePoint("train", t));
            for (const auto& t : o->held) b.heldOut.push_back(parseCollapsePoint("held-out", t));
            if (o->modes < 1) throw InputError("modes", std::to_string(o->modes), "1 or more");
            if (o->pressure != "lithostatic" && o->pressure != "recovered")
                throw InputError("pressure", o->pressure, "lithostatic or recovered");
            b.options.modes = o->modes;
            b.options.pressure = o->pressure == "recovered" ? rom::PressureClosure::recovered : rom::PressureClosure::lithostatic;
            b.out = o->out;
            b.coarseCells = o->coarse;
            b.progress = !o->json;
            const auto j = experiments::runRomBench(b);
            if (o->json) {
                std::cout << j.dump(2) << '\n';
                return 0;
            }
            std::cout << std::setprecision(3) << "collapse, " << j["cells"] << " cells: " << j["train_runs"]
                      << " training runs, " << j["held_out_runs"] << " held out; Galerkin " << j["modes"] << " modes, "
                      << j["pressure"].get<std::string>() << " pressure\n"
                      << "  mean time per answer: full " << j["mean_seconds"]["full"].get<double>() << " s, Galerkin "
                      << j["mean_seconds"]["galerkin"].get<double>() << " s (" << j["speedup"]["galerkin"].get<double>()
                      << "x), POD regression " << j["mean_seconds"]["pod_regression"].get<double>() << " s ("
                      << j["speedup"]["pod_regression"].get<double>() << "x), kriging "
                      << j["mean_seconds"]["kriging"].get<double>() << " s ("
                      << j["speedup"]["kriging"].get<double>() << "x)\n";
            if (!j["hyper"].is_null())
                std::cout << "  Galerkin hyper-reduced: mu(I) term at " << j["hyper"]["points"] << " cells, convection at "
                          << j["hyper"]["convection_points"] << " (training errors " << j["hyper"]["training_error"].get<double>()
                          << ", " << j["hyper"]["convection_training_error"].get<double>() << "): " << j["hyper"]["mean_seconds"].get<double>() << " s ("
                          << j["hyper"]["speedup"].get<double>() << "x)\n";
            std::cout << "  offline: training runs "
                      << j["offline"]["full_runs_seconds"].get<double>() << " s, Galerkin build "
                      << j["offline"]["galerkin_build_seconds"].get<double>() << " s; break-even after "
                      << j["break_even_answers"]["galerkin"].get<double>() << " answers (Galerkin), "
                      << j["break_even_answers"]["kriging"].get<double>() << " (kriging)\n"
                      << readFile(j["table"].get<std::string>()) << "plot: " << j["plot"].get<std::string>() << "\n\n"
                      << readFile(j["pareto_table"].get<std::string>()) << "plot: " << j["pareto_plot"].get<std::string>() << '\n';
            if (j.contains("warning")) std::cout << "warning: " << j["warning"].get<std::string>() << '\n';
            return 0;
        };
    });
}

}  // namespace mixload::app
