// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload bench pareto-mixer`: time against error for the mixer loading on a hold-out campaign.
#include <iomanip>
#include <iostream>

#include "app/commands.hpp"
#include "bench/mixer_pareto.hpp"
#include "common/atomic_file.hpp"

namespace mixload::app {

namespace {
struct BenchParetoMixer {
    std::string train, holdout, dir = "runs/campaigns", out = "runs/bench-mixer-pareto";
    std::vector<std::string> coarse;
    bool json = false;
};
}  // namespace

void addBenchParetoMixer(CLI::App* bench, Action& action) {
    auto o = std::make_shared<BenchParetoMixer>();
    auto* c = bench->add_subcommand(
        "pareto-mixer",
        "Mixer loading: time against error on a hold-out campaign's steady runs for full runs on coarser meshes (the same "
        "design), the loading surrogate (kriging, response surface) and the POD regression fitted on a training campaign: "
        "per-run table, Pareto table and PNG");
    c->add_option("--campaign", o->train, "Training campaign (on the hold-out's mesh)")->required();
    c->add_option("--holdout", o->holdout, "Hold-out campaign (its full runs are the reference)")->required();
    c->add_option("--coarse", o->coarse, "The hold-out's design on coarser meshes (campaign names; repeatable)");
    c->add_option("--dir", o->dir, "Where the campaigns live")->capture_default_str();
    c->add_option("--out", o->out, "Output directory")->capture_default_str();
    c->add_flag("--json", o->json, "Print JSON");
    c->callback([&action, o] {
        action = [o] {
            experiments::MixerPareto b;
            b.train = {o->train, o->dir};
            b.holdout = {o->holdout, o->dir};
            for (const auto& n : o->coarse) b.coarse.push_back({n, o->dir});
            b.out = o->out;
            const auto j = experiments::runMixerPareto(b);
            if (o->json) {
                std::cout << j.dump(2) << '\n';
                return 0;
            }
            std::cout << "mixer loading: " << j["holdout_steady_runs"] << " steady hold-out runs of " << o->holdout << ", models on "
                      << j["train_steady_runs"] << " steady runs of " << o->train << "\n\n"
                      << readFile(j["runs_table"].get<std::string>()) << '\n'
                      << readFile(j["pareto_table"].get<std::string>()) << "plot: " << j["pareto_plot"].get<std::string>() << '\n';
            for (const auto& n : j["notes"]) std::cout << "note: " << n.get<std::string>() << '\n';
            if (j.contains("pareto_warning")) std::cout << "warning: " << j["pareto_warning"].get<std::string>() << '\n';
            return 0;
        };
    });
}

}  // namespace mixload::app
