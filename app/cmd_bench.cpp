// SPDX-License-Identifier: GPL-3.0-or-later
// Benchmarks print time and quality side by side; they are not tests.
#include <filesystem>
#include <iostream>

#include "app/collapse_options.hpp"
#include "app/commands.hpp"
#include "run/collapse_job.hpp"

namespace mixload::app {

namespace {
struct BenchCollapse {
    CollapseOptions scene;
    std::vector<int> nps{1, 2};
    std::string out = "runs/bench-collapse";
    bool json = false;
};
}  // namespace

void addBench(CLI::App& app, Action& action) {
    auto* bench = app.add_subcommand("bench", "Benchmarks (time and accuracy side by side)");
    bench->require_subcommand(1);
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
}

}  // namespace mixload::app
