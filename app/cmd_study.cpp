// SPDX-License-Identifier: GPL-3.0-or-later
#include <iostream>

#include "app/collapse_options.hpp"
#include "app/commands.hpp"
#include "common/atomic_file.hpp"
#include "studies/collapse_study.hpp"

namespace mixload::app {

namespace {
struct StudyCmd {
    CollapseOptions base;
    std::vector<std::string> materials{"quartz", "copper"};
    std::vector<double> aspects{0.5, 1, 2, 3, 4, 5, 6};
    std::vector<int> cells{30};
    std::vector<std::string> rheologies{"muI"};
    std::string out = "runs/studies/collapse";
    int jobs = 2;
    bool json = false;
};
}  // namespace

void addStudy(CLI::App& app, Action& action) {
    auto* study = app.add_subcommand("study", "Offline studies (many full runs; resumable)");
    study->require_subcommand(1);
    auto* c = study->add_subcommand(
        "collapse", "Collapse sweep over materials x rheologies x aspect ratios x meshes: table + PNG");
    auto o = std::make_shared<StudyCmd>();
    o->base.add(c);
    c->add_option("--materials", o->materials, "Materials to sweep")->capture_default_str()->delimiter(',');
    c->add_option("--aspects", o->aspects, "Aspect ratios to sweep")->capture_default_str()->delimiter(',');
    c->add_option("--meshes", o->cells, "Cells per column length to sweep")->capture_default_str()->delimiter(',');
    c->add_option("--rheologies", o->rheologies, "Rheologies to sweep")->capture_default_str()->delimiter(',');
    c->add_option("--out", o->out, "Study directory (runs are kept and reused)")->capture_default_str();
    c->add_option("--jobs", o->jobs, "Concurrent serial runs")->capture_default_str();
    c->add_flag("--json", o->json, "Print JSON");
    c->callback([&action, o] {
        action = [o] {
            experiments::CollapseStudy st;
            // Every scene is validated before the first run starts.
            for (const auto& mat : o->materials)
                for (const auto& rh : o->rheologies)
                    for (double a : o->aspects)
                        for (int n : o->cells) {
                            CollapseOptions opt = o->base;
                            opt.material = mat;
                            opt.rheology = rh;
                            opt.aspect = a;
                            opt.cellsPerLength = n;
                            st.scenes.push_back(opt.scene());
                        }
            st.out = o->out;
            st.jobs = o->jobs;
            st.progress = !o->json;
            const auto r = experiments::runCollapseStudy(st);
            if (o->json) std::cout << r.dump(2) << '\n';
            else std::cout << readFile(r["table_md"].get<std::string>()) << "plot: " << r["plot"].get<std::string>() << '\n';
            // A study with a failed run is not a finished study.
            for (const auto& row : r["rows"])
                if (row.contains("error")) return 1;
            return 0;
        };
    });
}

}  // namespace mixload::app
