// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload sensitivity`: Sobol indices of the loading over a box of inputs, from a surrogate.
#include <iomanip>
#include <iostream>

#include "app/commands.hpp"
#include "app/point_options.hpp"
#include "common/input_error.hpp"
#include "doe/parameter_space.hpp"
#include "sensitivity/surrogate_sensitivity.hpp"

namespace mixload::app {

namespace {

struct SensitivityCmd {
    std::string model, ranges = std::string(MIXLOAD_DATA_DIR) + "/campaigns/mixer-avicel-ranges.toml", out = "runs/sensitivity";
    PointOptions at;
    int n = 8192, bootstrap = 500;
    bool json = false;
};

int run(const SensitivityCmd& o) {
    requireRange("n", o.n, 64, 1 << 22);
    requireRange("bootstrap", o.bootstrap, 0, 100000);
    const auto space = experiments::loadRanges(o.ranges);
    // Inputs the box leaves out stay at the paper's reference point unless given.
    const auto held = o.at.orPaperReference();
    const auto model = surrogates::Surrogate::load(o.model.empty() ? defaultModelPath() : o.model);
    auto j = experiments::surrogateSensitivity(model, space, held, o.n, o.bootstrap, o.out);
    j["model"] = o.model.empty() ? defaultModelPath() : o.model;
    j["ranges"] = o.ranges;
    if (o.json) {
        std::cout << j.dump(2) << '\n';
        return 0;
    }
    std::cout << "Sobol indices of M from " << j["model"].get<std::string>() << " (" << j["model_source"].get<std::string>() << ")\n  over "
              << o.ranges << ", " << j["evaluations"] << " predictions, 90% intervals from " << o.bootstrap << " bootstrap resamples\n"
              << std::fixed << std::setprecision(3);
    for (const auto& r : j["indices"])
        std::cout << "  " << std::left << std::setw(10) << r["input"].get<std::string>() << std::right << " first " << r["first"].get<double>()
                  << " (" << r["first_ci90"][0].get<double>() << " .. " << r["first_ci90"][1].get<double>() << ")  total "
                  << r["total"].get<double>() << " (" << r["total_ci90"][0].get<double>() << " .. " << r["total_ci90"][1].get<double>()
                  << ")\n";
    const double outside = j["outside_training_box"];
    if (outside > 0)
        std::cerr << "mixload: warning: " << std::fixed << std::setprecision(1) << 100 * outside
                  << "% of the samples lie outside the model's training box: those indices are extrapolation\n";
    std::cout << "  table " << j["table"].get<std::string>();
    if (!j["plot"].is_null()) std::cout << ", plot " << j["plot"].get<std::string>();
    std::cout << '\n';
    return 0;
}

}  // namespace

void addSensitivity(CLI::App& app, Action& action) {
    auto o = std::make_shared<SensitivityCmd>();
    auto* cmd = app.add_subcommand("sensitivity",
                                   "Sobol indices (first-order and total, with bootstrap intervals) of the loading M over a box of inputs, from a surrogate");
    cmd->add_option("--model", o->model, "Model file (default: the shipped kriging model)");
    cmd->add_option("--ranges", o->ranges, "Box of inputs (a campaign ranges file: mu_s, delta_mu, i0, d, rho, feed_kg_h, rpm)")
        ->capture_default_str();
    cmd->add_option("--n", o->n, "Base samples (n (k + 2) predictions)")->capture_default_str();
    cmd->add_option("--bootstrap", o->bootstrap, "Bootstrap resamples for the 90% intervals")->capture_default_str();
    cmd->add_option("--out", o->out, "Directory for sensitivity.md, .csv and .png")->capture_default_str();
    o->at.add(cmd, "", "held at (inputs the box leaves out; default the paper's reference point): ");
    cmd->add_flag("--json", o->json, "Print JSON");
    cmd->callback([&action, o] { action = [o] { return run(*o); }; });
}

}  // namespace mixload::app
