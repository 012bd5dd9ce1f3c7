// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload plane`: M over a plane of two inputs from a surrogate, with what-if arrows and the full
// runs on the plane (the paper's Fig. 8: M over mu_s and rho).
#include <iostream>

#include "app/commands.hpp"
#include "app/point_options.hpp"
#include "common/input_error.hpp"
#include "sensitivity/input_plane.hpp"

namespace mixload::app {

namespace {

struct PlaneCmd {
    std::string model, x = "mu_s", y = "rho", xRange = "0.2:0.42", yRange = "250:600", checks, out = "runs/plane";
    std::vector<std::string> arrows{"rho=+50%,mu_s=-10%", "rho=+50%,mu_s=-32%"};
    PointOptions at;
    int n = 41;
    double tol = 0.01;
    bool json = false;
};

size_t inputIndex(const std::string& field, const std::string& name) {
    for (size_t k = 0; k < surrogates::kInputs; ++k)
        if (name == surrogates::kInputSpecs[k].name) return k;
    throw InputError(field, name, "mu_s|mu_d|i0|d|rho|feed_kg_h|rpm");
}

experiments::PlaneAxis axis(const std::string& field, const std::string& name, const std::string& range) {
    experiments::PlaneAxis a;
    a.input = inputIndex(field, name);
    const auto colon = range.find(':');
    try {
        if (colon == std::string::npos) throw std::invalid_argument(range);
        a.lo = std::stod(range.substr(0, colon));
        a.hi = std::stod(range.substr(colon + 1));
    } catch (const std::exception&) {
        throw InputError(field + "-range", range, "LO:HI, e.g. 0.2:0.42");
    }
    return a;
}

int run(const PlaneCmd& o) {
    requireRange("on-plane-tol", o.tol, 0.0, 0.5);
    experiments::PlaneSpec spec;
    spec.base = o.at.orPaperReference();
    spec.x = axis("x", o.x, o.xRange);
    spec.y = axis("y", o.y, o.yRange);
    spec.n = o.n;
    spec.onPlaneTol = o.tol;
    for (const auto& a : o.arrows) {
        experiments::PlaneArrow arrow{a, spec.base};
        size_t from = 0;
        while (from <= a.size()) {
            const auto comma = a.find(',', from);
            applyChange(arrow.to, a.substr(from, comma == std::string::npos ? std::string::npos : comma - from), "arrow");
            if (comma == std::string::npos) break;
            from = comma + 1;
        }
        spec.arrows.push_back(arrow);
    }
    if (!o.checks.empty()) spec.checks = surrogates::readTable(o.checks);
    const std::string path = o.model.empty() ? defaultModelPath() : o.model;
    const auto model = surrogates::Surrogate::load(path);
    const auto j = experiments::inputPlane(model, path, spec, o.out);
    if (o.json) {
        std::cout << j.dump(2) << '\n';
        return 0;
    }
    std::cout << "M over (" << o.x << ", " << o.y << ") from " << path << " (" << j["source"].get<std::string>() << ")\n  base M = "
              << formatNumber(j["base_kg"].get<double>()) << " kg; " << j["grid_points"] << " grid points, "
              << j["outside_training_box"] << " outside the training box\n";
    for (const auto& a : j["arrows"])
        std::cout << "  " << a["change"].get<std::string>() << ": M = " << formatNumber(a["loading_kg"].get<double>()) << " kg, dM/M "
                  << formatNumber(100 * a["dm_rel"].get<double>()) << "%\n";
    if (j.contains("checks_mean_abs_error"))
        std::cout << "  " << j["checks"].size() << " full runs on the plane: mean |error| "
                  << formatNumber(100 * j["checks_mean_abs_error"].get<double>()) << "%, " << j["checks_covered"]
                  << " inside the 95% interval\n";
    else if (!o.checks.empty())
        std::cout << "  no full run of " << o.checks << " lies on the plane\n";
    std::cout << "  table " << j["table"].get<std::string>();
    if (!j["plot"].is_null()) std::cout << ", plot " << j["plot"].get<std::string>();
    std::cout << '\n';
    return 0;
}

}  // namespace

void addPlane(CLI::App& app, Action& action) {
    auto o = std::make_shared<PlaneCmd>();
    auto* cmd = app.add_subcommand("plane",
                                   "M over a plane of two inputs from a surrogate, with what-if arrows and the full runs on the plane "
                                   "(default: the paper's Fig. 8, mu_s x rho, its two arrows): table + PNG");
    cmd->add_option("--model", o->model, "Model file (default: the shipped kriging model)");
    cmd->add_option("--x", o->x, "Input on the x axis")->capture_default_str();
    cmd->add_option("--x-range", o->xRange, "LO:HI of the x axis (SI units)")->capture_default_str();
    cmd->add_option("--y", o->y, "Input on the y axis")->capture_default_str();
    cmd->add_option("--y-range", o->yRange, "LO:HI of the y axis (SI units)")->capture_default_str();
    cmd->add_option("--arrow", o->arrows, "A what-if from the base drawn as an arrow: comma-separated changes, e.g. rho=+50%,mu_s=-10% (repeatable; default the paper's two)")
        ->capture_default_str();
    cmd->add_option("--checks", o->checks, "Full runs (CSV as `campaign export` writes): those on the plane are compared and drawn");
    cmd->add_option("--on-plane-tol", o->tol, "A run lies on the plane when its other inputs are within this share of the base's")
        ->capture_default_str();
    cmd->add_option("--n", o->n, "Grid points per axis")->capture_default_str();
    cmd->add_option("--out", o->out, "Directory for plane.md, .csv and .png")->capture_default_str();
    o->at.add(cmd, "", "base (default the paper's reference point): ");
    cmd->add_flag("--json", o->json, "Print JSON");
    cmd->callback([&action, o] { action = [o] { return run(*o); }; });
}

}  // namespace mixload::app
