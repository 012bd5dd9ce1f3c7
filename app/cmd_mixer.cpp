// SPDX-License-Identifier: GPL-3.0-or-later
#include <iomanip>
#include <iostream>

#include "app/commands.hpp"
#include "app/mixer_options.hpp"
#include "post/run_profile.hpp"
#include "common/input_error.hpp"
#include "run/label_protocol.hpp"
#include "run/mixer_job.hpp"

namespace mixload::app {

namespace {
struct MixerCmd {
    MixerOptions scene;
    int np = 1;
    std::string out;
    bool json = false;
    bool rerun = false;
    bool snapshots = false;
    bool profile = false;
    std::string warmFrom;
    std::string protocol = "scene";
};
}  // namespace

void addMixer(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "mixer", "Run the 3D continuous mixer (mu(I) powder + air) to a steady loading");
    auto o = std::make_shared<MixerCmd>();
    o->scene.add(cmd);
    cmd->add_option("--np", o->np, "MPI ranks (OpenFOAM decomposition)")->capture_default_str();
    cmd->add_option("--out", o->out, "Run directory (default runs/mixer-<scene hash>); resumes");
    cmd->add_flag("--rerun", o->rerun, "Run again even if the run directory holds a finished result");
    cmd->add_flag("--snapshots", o->snapshots,
                  "Export the run's written times to <run dir>/snapshots.h5 (+ .xmf) at the end");
    cmd->add_flag("--profile", o->profile,
                  "Record and print where the time steps and the time go (Courant peaks, stages, "
                  "solver iterations)");
    cmd->add_option("--warm-from", o->warmFrom,
                    "Start from the latest fields of this mixer run directory (mapped onto this "
                    "mesh), or from the powder fraction of a .h5 field file of this mesh (e.g. from "
                    "`rom regression --at ... --fields`), instead of the deposit");
    cmd->add_option("--protocol", o->protocol,
                    "scene (the scene's deposit and windows, or those given) | label (the campaigns' label "
                    "protocol: a fixed 0.05 kg deposit, windows of one residence time; the result says whether it is a label)")
        ->capture_default_str();
    cmd->add_flag("--json", o->json, "Print the result as JSON");
    cmd->callback([&action, o] {
        action = [o] {
            run::MixerJob job;
            if (o->protocol != "scene" && o->protocol != "label") throw InputError("protocol", o->protocol, "scene | label");
            if (o->protocol == "label" && !o->warmFrom.empty())
                throw InputError("warm-from", o->warmFrom, "no warm start under --protocol label (a label starts from its deposit)");
            scene::MixerOverrides m = o->scene;
            if (o->protocol == "label") run::applyLabelProtocol(m);
            job.scene = m.build();
            job.np = o->np;
            job.out = o->out;
            job.progress = !o->json;
            job.reuse = !o->rerun;
            job.snapshots = o->snapshots;
            job.profile = o->profile;
            job.warmFrom = o->warmFrom;
            const auto r = run::runMixer(job);
            if (o->json) {
                std::cout << r.dump(2) << '\n';
                return 0;
            }
            const auto& s = job.scene;
            std::cout << std::setprecision(4) << "mixer " << s.name << ", " << s.method << ", "
                      << s.rpm << " rpm, feed " << s.feedKgH << " kg/h, " << r["cells"]
                      << " cells, np = " << job.np << "\n  loading M = "
                      << r["loading_kg"].get<double>() << " kg (std "
                      << r["loading_std_kg"].get<double>() << " kg over the final window)"
                      << "\n  steady: " << (r["steady"].get<bool>() ? "yes" : "NO (cap reached)")
                      << "\n  label: " << (r.value("label", false) ? std::string("yes (") + r.value("protocol", "") + ")"
                                                                    : "no (" + r.value("not_label_because", std::string()) + ")")
                      << "\n  outflow " << r["outflow_kg_h"].get<double>() << " kg/h"
                      << "\n  powder balance error "
                      << (r["powder_balance_error"].is_null() ? std::string("n/a (pseudo-time)")
                                                               : r["powder_balance_error"].dump())
                      << "\n  wall " << r["wall_seconds"].get<double>() << " s, core "
                      << r["core_seconds"].get<double>() << " s"
                      << "\n  run dir " << r["run_dir"].get<std::string>() << "\n  plot "
                      << r["plot"].get<std::string>() << '\n';
            if (r.contains("snapshots"))
                std::cout << "  snapshots " << r["snapshots"].get<std::string>() << '\n';
            if (r.contains("profile")) std::cout << post::formatRunProfile(r["profile"]);
            if (r.contains("warning"))
                std::cout << "  WARNING: " << r["warning"].get<std::string>() << '\n';
            return 0;
        };
    });
}

}  // namespace mixload::app
