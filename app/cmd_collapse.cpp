// SPDX-License-Identifier: GPL-3.0-or-later
#include <iostream>

#include "app/collapse_options.hpp"
#include "app/commands.hpp"
#include "run/collapse_job.hpp"

namespace mixload::app {

namespace {
struct CollapseCmd {
    CollapseOptions scene;
    int np = 1;
    std::string out;
    bool json = false;
    bool rerun = false;
    bool snapshots = false;
};
}  // namespace

void addCollapse(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand("collapse", "Run the 2D granular column collapse with mu(I) in interFoam");
    auto o = std::make_shared<CollapseCmd>();
    o->scene.add(cmd);
    cmd->add_option("--np", o->np, "MPI ranks (OpenFOAM decomposition)")->capture_default_str();
    cmd->add_option("--out", o->out, "Run directory (default runs/collapse-<scene hash>)");
    cmd->add_flag("--rerun", o->rerun, "Run again even if the run directory holds a finished result");
    cmd->add_flag("--snapshots", o->snapshots,
                  "Export the run's written times to <run dir>/snapshots.h5 (+ .xmf) at the end");
    cmd->add_flag("--json", o->json, "Print the result as JSON");
    cmd->callback([&action, o] {
        action = [o] {
            run::CollapseJob job;
            job.scene = o->scene.scene();
            job.np = o->np;
            job.out = o->out;
            job.progress = !o->json;
            job.reuse = !o->rerun;
            job.snapshots = o->snapshots;
            const auto r = run::runCollapse(job);
            if (o->json) {
                std::cout << r.dump(2) << '\n';
                return 0;
            }
            std::cout << "collapse of " << job.scene.material.name << ", a = " << job.scene.aspect
                      << ", " << job.scene.rheology << ", " << r["cells"] << " cells, np = " << job.np
                      << "\n  L*f = " << r["runout_star"].get<double>()
                      << "\n  H*f = " << r["height_star"].get<double>()
                      << "\n  stopped by " << r["stopped_by"].get<std::string>() << " at t = "
                      << r["end_time_tstar"].get<double>() << " t* (t* = " << r["t_star"].get<double>()
                      << " s)\n  powder volume change " << r["powder_mass_error"].get<double>()
                      << "\n  wall time " << r["wall_seconds"].get<double>() << " s"
                      << "\n  run dir " << r["run_dir"].get<std::string>()
                      << "\n  plot " << r["plot"].get<std::string>() << '\n';
            if (r.contains("snapshots"))
                std::cout << "  snapshots " << r["snapshots"].get<std::string>() << '\n';
            return 0;
        };
    });
}

}  // namespace mixload::app
