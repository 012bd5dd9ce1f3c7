// SPDX-License-Identifier: GPL-3.0-or-later
// Benchmarks print time and quality side by side; they are not tests.
#include <filesystem>
#include <iomanip>
#include <iostream>

#include <sstream>

#include "app/collapse_options.hpp"
#include "app/commands.hpp"
#include "app/mixer_options.hpp"
#include "bench/mixer_steady_bench.hpp"
#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "post/mixer_results.hpp"
#include "run/collapse_job.hpp"
#include "run/mixer_job.hpp"

namespace mixload::app {

namespace {
struct BenchCollapse {
    CollapseOptions scene;
    std::vector<int> nps{1, 2};
    std::string out = "runs/bench-collapse";
    bool json = false;
};

struct BenchMixer {
    MixerOptions scene;
    std::vector<std::string> methods{"mrf", "lts", "sm"};
    int np = 1;
    std::string out = "runs/bench-mixer";
    bool json = false;
    bool steady = false;
    std::vector<std::string> points{"39:5", "39:45", "254:45"};
    bool noBaseline = false, noWarm = false, resume = false;
};

std::pair<double, double> parsePoint(const std::string& text) {
    const auto colon = text.find(':');
    const auto rpm = colon == std::string::npos ? std::nullopt : parseNumber(text.substr(0, colon));
    const auto feed = colon == std::string::npos ? std::nullopt : parseNumber(text.substr(colon + 1));
    if (!rpm || !feed) throw InputError("points", text, "rpm:feed_kg_h, e.g. 39:5");
    return {*rpm, *feed};
}

// One method's row: cost per simulated second and per revolution (per iteration for lts, whose
// pseudo-time is not time), the time to a steady loading if the run got there, and the powder
// balance, because a cheap answer that leaks is not an answer.
nlohmann::json mixerRow(const scene::MixerScene& s, const nlohmann::json& r, int np) {
    const bool lts = s.method == "lts";
    const double solver = r["solver_wall_seconds"].get<double>();
    const double span = r["end_time_s"].get<double>() - post::startTime(r);
    nlohmann::json row{{"method", s.method},
                       {"cells", r["cells"]},
                       {"np", np},
                       {"wall_seconds", r["wall_seconds"]},
                       {"solver_wall_seconds", solver},
                       {"core_seconds", r["core_seconds"]},
                       {"simulated", span},
                       {"simulated_unit", lts ? "iteration" : "s"},
                       {"final_loading_kg", r["final_loading_kg"]},
                       {"steady", r["steady"]},
                       {"steady_time_s", r["steady_time_s"]},
                       {"wall_seconds_to_steady", r["steady"].get<bool>() ? r["wall_seconds"] : nlohmann::json()},
                       {"powder_leak_kg_h", r.value("powder_leak_kg_h", nlohmann::json())},
                       {"powder_balance_ok", r.value("powder_balance_ok", nlohmann::json())}};
    if (lts) {
        row["wall_seconds_per_iteration"] = solver / span;
        row["wall_seconds_per_simulated_s"] = nullptr;
        row["wall_seconds_per_revolution"] = nullptr;
        row["core_seconds_per_simulated_s"] = nullptr;
    } else {
        row["wall_seconds_per_simulated_s"] = solver / span;
        row["core_seconds_per_simulated_s"] = solver * np / span;
        row["wall_seconds_per_revolution"] = solver / span * s.revolutionTime();
        row["core_seconds_per_revolution"] = solver * np / span * s.revolutionTime();
    }
    return row;
}
}  // namespace

void addBench(CLI::App& app, Action& action) {
    auto* bench = app.add_subcommand("bench", "Benchmarks (time and accuracy side by side)");
    bench->require_subcommand(1);
    addBenchPredict(bench, action);
    addBenchRom(bench, action);
    addBenchParetoMixer(bench, action);
    auto* c = bench->add_subcommand("collapse", "Collapse a = 2 at Li/30: wall time, cells, cell-steps/s, serial vs MPI");
    auto o = std::make_shared<BenchCollapse>();
    o->scene.add(c);
    c->add_option("--np", o->nps, "Rank counts to compare, in one run")->capture_default_str();
    c->add_option("--out", o->out, "Scratch directory (replaced)")->capture_default_str();
    c->add_flag("--json", o->json, "Print JSON");
    c->callback([&action, o] {
        action = [o] {
            const auto s = o->scene.scene();
            nlohmann::json rows = nlohmann::json::array();
            std::filesystem::remove_all(o->out);
            double serialLf = 0;
            for (int np : o->nps) {
                run::CollapseJob job;
                job.scene = s;
                job.np = np;
                job.out = std::filesystem::path(o->out) / ("np" + std::to_string(np));
                job.progress = !o->json;
                job.reuse = false;
                const auto r = run::runCollapse(job);
                const double steps = r["time_steps"].get<double>();
                const double wall = r["solver_wall_seconds"].get<double>();
                if (np == o->nps.front()) serialLf = r["runout_star"].get<double>();
                rows.push_back({{"np", np},
                                {"cells", r["cells"]},
                                {"time_steps", steps},
                                {"solver_wall_seconds", wall},
                                {"core_seconds", wall * np},
                                {"cell_steps_per_second", r["cells"].get<double>() * steps / wall},
                                {"runout_star", r["runout_star"]},
                                {"runout_change_vs_first", r["runout_star"].get<double>() - serialLf},
                                {"stopped_by", r["stopped_by"]}});
            }
            const nlohmann::json out = {{"benchmark", "collapse"}, {"scene", s.toJson()}, {"runs", rows}};
            if (o->json) {
                std::cout << out.dump(2) << '\n';
                return 0;
            }
            std::cout << "collapse benchmark: " << s.material.name << ", a = " << s.aspect
                      << ", dx = Li/" << s.cellsPerLength << "\n";
            std::printf("%4s %8s %7s %10s %12s %16s %8s\n", "np", "cells", "steps", "wall [s]",
                        "core [s]", "cell-steps/s", "L*f");
            for (const auto& r : rows)
                std::printf("%4d %8ld %7.0f %10.1f %12.1f %16.3g %8.3f\n", r["np"].get<int>(),
                            r["cells"].get<long>(), r["time_steps"].get<double>(),
                            r["solver_wall_seconds"].get<double>(), r["core_seconds"].get<double>(),
                            r["cell_steps_per_second"].get<double>(), r["runout_star"].get<double>());
            return 0;
        };
    });

    auto* m = bench->add_subcommand(
        "mixer", "Mixer on one mesh: cost per simulated second and per revolution of mrf, lts and sm, "
                 "time to steady, powder balance (short runs: --end-time defaults to 0.5 s and "
                 "--lts-iterations to 100 here)");
    auto mo = std::make_shared<BenchMixer>();
    mo->scene.add(m, /*withMethod=*/false);
    m->add_option("--methods", mo->methods, "Methods to compare, in one run")
        ->delimiter(',')
        ->capture_default_str();
    m->add_option("--np", mo->np, "MPI ranks for every method")->capture_default_str();
    m->add_option("--out", mo->out, "Scratch directory (replaced)")->capture_default_str();
    m->add_flag("--json", mo->json, "Print JSON");
    m->add_flag("--steady", mo->steady,
                "Instead: run --points to their steady verdict with the baseline setup (legacy "
                "numerics, cold) and the current one, cold and warm (from the baseline's field), "
                "with profiles; prints wall time to the verdict beside the loading");
    m->add_option("--points", mo->points, "With --steady: rpm:feed points")
        ->delimiter(',')
        ->capture_default_str();
    m->add_flag("--no-baseline", mo->noBaseline, "With --steady: skip the baseline runs");
    m->add_flag("--no-warm", mo->noWarm, "With --steady: skip the warm runs");
    m->add_flag("--resume", mo->resume,
                "With --steady: keep --out and reuse its finished runs (their measured times)");
    m->callback([&action, mo] {
        action = [mo] {
            if (mo->steady) {
                experiments::SteadyBench b;
                b.scene = mo->scene.build();
                for (const auto& p : mo->points) b.points.push_back(parsePoint(p));
                requireRange("np", mo->np, 1, 256);
                b.np = mo->np;
                b.baseline = !mo->noBaseline;
                b.warm = !mo->noWarm;
                b.resume = mo->resume;
                b.out = mo->out;
                b.progress = !mo->json;
                const auto res = experiments::runSteadyBench(b);
                writeFileAtomic(std::filesystem::path(mo->out) / "bench.json", res.dump(2));
                if (mo->json) std::cout << res.dump(2) << '\n';
                else std::cout << experiments::formatSteadyBench(res);
                return 0;
            }
            // Short runs unless the user asks for more: a benchmark measures rates, not answers.
            MixerOptions opts = mo->scene;
            if (!opts.endTime) opts.endTime = 0.5;
            if (!opts.ltsIterations) opts.ltsIterations = 100;
            for (const auto& meth : mo->methods)
                if (meth != "mrf" && meth != "lts" && meth != "sm")
                    throw InputError("methods", meth, "mrf|lts|sm");
            requireRange("np", mo->np, 1, 256);
            std::vector<scene::MixerScene> scenes;
            for (const auto& meth : mo->methods) {
                opts.method = meth;
                scenes.push_back(opts.build());  // every input checked before anything runs
            }
            std::filesystem::remove_all(mo->out);
            nlohmann::json rows = nlohmann::json::array();
            for (const auto& s : scenes) {
                run::MixerJob job;
                job.scene = s;
                job.np = mo->np;
                job.out = std::filesystem::path(mo->out) / s.method;
                job.progress = !mo->json;
                job.reuse = false;
                rows.push_back(mixerRow(s, run::runMixer(job), mo->np));
            }
            const nlohmann::json out = {{"benchmark", "mixer"}, {"scene", scenes.front().toJson()},
                                        {"runs", rows}};
            if (mo->json) {
                std::cout << out.dump(2) << '\n';
                return 0;
            }
            const auto& s0 = scenes.front();
            std::cout << "mixer benchmark: " << s0.name << ", " << s0.rpm << " rpm, feed "
                      << s0.feedKgH << " kg/h, mesh " << s0.mesh << ", np " << mo->np << "\n";
            std::printf("%-4s %7s %10s %12s %14s %14s %8s %12s\n", "", "cells", "simulated",
                        "solver [s]", "wall/sim s", "wall/rev", "steady", "leak [kg/h]");
            for (const auto& r : rows) {
                auto num = [](const nlohmann::json& v) {
                    std::ostringstream os;
                    if (v.is_null()) os << "-";
                    else os << std::setprecision(4) << v.get<double>();
                    return os.str();
                };
                std::printf("%-4s %7ld %8.4g %-2s %12.1f %14s %14s %8s %12s\n",
                            r["method"].get<std::string>().c_str(), r["cells"].get<long>(),
                            r["simulated"].get<double>(),
                            r["simulated_unit"] == "s" ? "s" : "it",
                            r["solver_wall_seconds"].get<double>(),
                            num(r["method"] == "lts" ? r["wall_seconds_per_iteration"]
                                                     : r["wall_seconds_per_simulated_s"]).c_str(),
                            num(r["wall_seconds_per_revolution"]).c_str(),
                            r["steady"].get<bool>() ? "yes" : "no",
                            num(r["powder_leak_kg_h"]).c_str());
            }
            std::cout << "(lts: wall/sim s is per pseudo-time iteration)\n";
            return 0;
        };
    });
}

}  // namespace mixload::app
