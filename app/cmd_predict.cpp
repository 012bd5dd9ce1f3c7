// SPDX-License-Identifier: GPL-3.0-or-later
// mixload predict and mixload whatif: the users' questions answered from a fitted surrogate.
#include <cmath>
#include <iomanip>
#include <iostream>
#include <map>
#include <sstream>

#include <toml++/toml.h>

#include "app/commands.hpp"
#include "app/point_options.hpp"
#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "model.hpp"
#include "whatif/whatif.hpp"

namespace mixload::app {

namespace {

using surrogates::kInputs;
using surrogates::kInputSpecs;
using surrogates::Point;

void warnOutside(const surrogates::Surrogate& m, const Point& x, const std::string& label = "") {
    std::cout.flush();  // keep the warning after what was already printed
    for (const auto& w : m.outsideBox(x))
        std::cerr << "mixload: warning: " << label << "outside the training box: " << w << '\n';
}

void warnOverfull(const std::string& label, double m, double fullBarrelKg) {
    std::cerr << "mixload: warning: " << label << "M = " << m << " kg exceeds a full barrel of this powder (" << fullBarrelKg
              << " kg): the model is not valid at this point\n";
}

struct PredictCmd {
    std::string model, batch, output;
    PointOptions point;
    bool json = false, extrapolate = false;
};

int predictBatch(const PredictCmd& o, const surrogates::Surrogate& m) {
    if (o.output.empty()) throw InputError("output", "(missing)", "-o OUT.csv with --batch");
    const auto points = surrogates::readInputs(o.batch);
    for (size_t r = 0; r < points.size(); ++r) {
        try {
            surrogates::requirePhysical(points[r]);
        } catch (const InputError& e) {
            throw InputError(o.batch + ": row " + std::to_string(r + 1) + ": " + e.what());
        }
    }
    auto ws = m.makeWorkspace();
    std::ostringstream os;
    os << std::setprecision(17);
    for (const auto& s : kInputSpecs) os << s.name << ',';
    os << "loading_kg,ci95_lo_kg,ci95_hi_kg,in_training_box,refused,above_full_barrel\n";
    size_t outside = 0, refused = 0, overfull = 0;
    for (const auto& x : points) {
        const auto p = m.predict(x, ws);
        for (double v : x) os << v << ',';
        // Rows too far outside the box get no number (as predict refuses them), unless --extrapolate.
        const bool refuse = !o.extrapolate && p.outside > surrogates::kMaxExtrapolation;
        if (refuse) os << ",,,false,true,\n";
        else os << p.m << ',' << p.lo << ',' << p.hi << ',' << (p.inBox ? "true" : "false") << ",false," << (p.overfull ? "true" : "false") << '\n';
        outside += !p.inBox;
        refused += refuse;
        overfull += !refuse && p.overfull;
    }
    writeFileAtomic(o.output, os.str());
    if (outside) std::cerr << "mixload: warning: " << outside << " of " << points.size() << " points lie outside the training box (in_training_box = false)\n";
    if (refused)
        std::cerr << "mixload: warning: " << refused << " of them lie more than " << formatNumber(100 * surrogates::kMaxExtrapolation)
                  << "% of a trained range beyond it and have no loading (refused = true; --extrapolate to predict them anyway)\n";
    if (overfull)
        std::cerr << "mixload: warning: " << overfull << " of the answers exceed a full barrel of their powder (above_full_barrel = true): "
                  << "the model is not valid there\n";
    if (o.json)
        std::cout << nlohmann::json{{"rows", points.size()}, {"outside_training_box", outside}, {"refused", refused},
                                    {"above_full_barrel", overfull}, {"output", o.output}}.dump(2) << '\n';
    else std::cout << points.size() << " predictions written to " << o.output << '\n';
    return 0;
}

int predict(const PredictCmd& o) {
    const std::string path = o.model.empty() ? defaultModelPath() : o.model;
    if (!o.batch.empty()) return predictBatch(o, surrogates::Surrogate::load(path));
    const Point x = o.point.point();  // validated before the model is even read
    const auto m = surrogates::Surrogate::load(path);
    if (!o.extrapolate) m.requireNearBox(x);
    auto ws = m.makeWorkspace();
    const auto p = m.predict(x, ws);
    warnOutside(m, x);
    if (p.clipped) std::cerr << "mixload: warning: the model's answer fell below zero and was cut at 0 kg\n";
    if (p.overfull) warnOverfull("", p.m, p.fullBarrelKg);
    if (o.json) {
        std::cout << experiments::predictionJson(m, x, p, path).dump(2) << '\n';
        return 0;
    }
    std::cout << std::setprecision(4) << "M = " << p.m << " kg";
    if (p.overfull) std::cout << " (above a full barrel of this powder, " << p.fullBarrelKg << " kg: not valid here)";
    else if (!std::isnan(p.lo)) std::cout << " (95% interval " << p.lo << " .. " << p.hi << " kg)";
    std::cout << "  [" << m.kind() << ", " << path << "]\n  model of " << m.sourceLabel() << "\n  "
              << experiments::regimeErrorLine(experiments::regimeErrorJson(m, x)) << '\n';
    return 0;
}

// --- whatif ------------------------------------------------------------------------------------

using experiments::kMaterial;

struct WhatifCmd {
    std::string model, baseFile, newFile;
    PointOptions base, changed;
    std::vector<std::string> changes, at;
    std::optional<double> feed, rpm;
    std::string report;
    std::vector<double> feeds{5, 15, 30, 45}, rpms{39, 100, 162, 254};  // the paper's feeds and the trends' speeds
    bool json = false, extrapolate = false;
};

// A formulation: the five material inputs (operating point slots unused).
Point formulationFromToml(const std::string& file) {
    toml::table t;
    try {
        t = toml::parse_file(file);
    } catch (const toml::parse_error& e) {
        throw InputError(file + ": " + std::string(e.description()) + " at line " +
                         std::to_string(e.source().begin.line));
    }
    Point x{};
    for (size_t k : kMaterial) {
        const auto v = t[kInputSpecs[k].name].value<double>();
        if (!v) throw InputError(file + ": key '" + kInputSpecs[k].name + "' (" + kInputSpecs[k].unit + ") is missing or not a number");
        x[k] = *v;
    }
    for (const auto& [key, _] : t)
        if (std::string(key.str()) != "name" &&
            std::none_of(kMaterial.begin(), kMaterial.end(), [&](size_t k) { return key.str() == kInputSpecs[k].name; }))
            throw InputError(file + ": unknown key '" + std::string(key.str()) + "' (allowed: mu_s, mu_d, i0, d, rho, name)");
    return x;
}

Point formulation(const std::string& file, const PointOptions& flags, const std::string& prefix, const Point* from) {
    Point x{};
    if (!file.empty()) x = formulationFromToml(file);
    else if (from) x = *from;
    for (size_t k : kMaterial) {
        if (flags.v[k]) x[k] = *flags.v[k];
        else if (file.empty() && !from)
            throw InputError(std::string("--") + prefix + (kInputSpecs[k].flag + 2), "(missing)",
                             missingInputHint(k) + ", or --base FILE.toml");
    }
    return x;
}

std::vector<std::pair<double, double>> operatingPoints(const WhatifCmd& o) {
    std::vector<std::pair<double, double>> pts;
    for (const auto& a : o.at) {
        const auto colon = a.find(':');
        try {
            if (colon == std::string::npos) throw std::invalid_argument(a);
            pts.emplace_back(std::stod(a.substr(0, colon)), std::stod(a.substr(colon + 1)));
        } catch (const std::exception&) {
            throw InputError("at", a, "FEED_KG_H:RPM, e.g. 5:39");
        }
    }
    if (o.feed || o.rpm) {
        if (!o.feed || !o.rpm) throw InputError(o.feed ? "rpm" : "feed-kg-h", "(missing)", "both --feed-kg-h and --rpm");
        pts.emplace_back(*o.feed, *o.rpm);
    }
    if (pts.empty()) throw InputError("operating point", "(missing)", "--feed-kg-h F --rpm R, or --at F:R (repeatable)");
    return pts;
}

int whatif(const WhatifCmd& o) {
    const Point a = formulation(o.baseFile, o.base, "", nullptr);
    Point b = formulation(o.newFile, o.changed, "new-", o.newFile.empty() ? &a : nullptr);
    for (const auto& c : o.changes) applyChange(b, c);
    const std::string path = o.model.empty() ? defaultModelPath() : o.model;
    if (!o.report.empty()) {
        const auto m = surrogates::Surrogate::load(path);
        auto r = experiments::whatifReport(m, path, a, b, o.feeds, o.rpms, o.report);
        if (o.json) {
            std::cout << r.dump(2) << '\n';
            return 0;
        }
        size_t outside = 0, overfull = 0;
        for (const auto& p : r["points"]) {
            outside += !(p["base"]["in_training_box"].get<bool>() && p["new"]["in_training_box"].get<bool>());
            overfull += p["base"]["above_full_barrel"].get<bool>() || p["new"]["above_full_barrel"].get<bool>();
        }
        std::cout << "what-if over " << r["points"].size() << " operating points from " << path << " (" << m.sourceLabel() << ")\n  table "
                  << r["table"].get<std::string>();
        if (!r["plot"].is_null()) std::cout << ", plot " << r["plot"].get<std::string>();
        std::cout << '\n';
        if (outside) std::cerr << "mixload: warning: " << outside << " of the points lie outside the model's training box (marked in the table)\n";
        if (overfull)
            std::cerr << "mixload: warning: at " << overfull
                      << " of the points a loading exceeds a full barrel of its powder: not valid there (marked in the table)\n";
        return 0;
    }
    const auto pts = operatingPoints(o);
    const auto m = surrogates::Surrogate::load(path);
    nlohmann::json out{{"model", path}, {"kind", m.kind()}, {"source", m.sourceLabel()}, {"points", nlohmann::json::array()}};
    for (size_t k : kMaterial) {
        out["base"][kInputSpecs[k].name] = a[k];
        out["new"][kInputSpecs[k].name] = b[k];
    }
    out["points"] = experiments::compareFormulations(m, path, a, b, pts, o.extrapolate);
    for (const auto& p : out["points"])
        for (const char* side : {"base", "new"}) {
            for (const auto& w : p[side].value("outside", nlohmann::json::array()))
                std::cerr << "mixload: warning: " << side << ": outside the training box: " << w.get<std::string>() << '\n';
            if (p[side].value("above_full_barrel", false))
                warnOverfull(std::string(side) + ": ", p[side]["loading_kg"].get<double>(), p[side]["full_barrel_kg"].get<double>());
        }
    if (o.json) {
        std::cout << out.dump(2) << '\n';
        return 0;
    }
    std::cout << std::setprecision(4) << "what-if with " << path << " (" << m.kind() << ", model of "
              << m.sourceLabel() << ")\n  base:";
    for (size_t k : kMaterial) std::cout << ' ' << kInputSpecs[k].name << '=' << a[k];
    std::cout << "\n  new: ";
    for (size_t k : kMaterial) std::cout << ' ' << kInputSpecs[k].name << '=' << b[k];
    std::cout << '\n';
    for (const auto& p : out["points"]) {
        std::cout << "  at " << p["feed_kg_h"].get<double>() << " kg/h, " << p["rpm"].get<double>()
                  << " rpm: M " << p["base"]["loading_kg"].get<double>() << " -> " << p["new"]["loading_kg"].get<double>()
                  << " kg, dM = " << p["delta_kg"].get<double>() << " kg (" << std::showpos
                  << 100 * p["delta_rel"].get<double>() << std::noshowpos << "%)";
        if (!p["delta_ci95_kg"].is_null())
            std::cout << ", 95% interval " << p["delta_ci95_kg"][0].get<double>() << " .. " << p["delta_ci95_kg"][1].get<double>()
                      << " kg (the two predictions' errors correlate by " << p["error_correlation"].get<double>()
                      << "; taken as independent " << p["delta_ci95_independent_kg"][0].get<double>() << " .. "
                      << p["delta_ci95_independent_kg"][1].get<double>() << " kg)";
        std::cout << "\n    one input at a time from the base:";
        for (const auto& at : p["attribution"])
            std::cout << ' ' << at["input"].get<std::string>() << ' ' << std::showpos << at["delta_kg"].get<double>()
                      << std::noshowpos << " kg;";
        std::cout << " interaction " << std::showpos << p["interaction_kg"].get<double>() << std::noshowpos << " kg\n";
        std::cout << "    " << experiments::regimeErrorLine(p["base"]["regime"]) << '\n';
    }
    return 0;
}

}  // namespace

void addPredict(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand("predict", "Predict the mixer loading M [kg] from a surrogate (microseconds). Inputs in SI units: --d in metres, --rho bulk density in kg/m3");
    auto o = std::make_shared<PredictCmd>();
    cmd->add_option("--model", o->model, "Model file (default: the shipped kriging model, data/models/)");
    o->point.add(cmd);
    cmd->add_option("--batch", o->batch, "CSV of points (columns mu_s, mu_d or delta_mu, i0, d, rho, feed_kg_h, rpm)");
    cmd->add_option("-o,--output", o->output, "CSV to write with --batch");
    cmd->add_flag("--extrapolate", o->extrapolate,
                  "Answer even far outside the training box (by default refused beyond 25% of an input's trained range)");
    cmd->add_flag("--json", o->json, "Print JSON: loading_kg, ci95_kg, in_training_box, model");
    cmd->callback([&action, o] { action = [o] { return predict(*o); }; });

    auto* w = app.add_subcommand("whatif", "Compare two formulations at operating points: M for each, dM with its uncertainty, and which inputs drive dM (SI units)");
    auto wo = std::make_shared<WhatifCmd>();
    w->add_option("--model", wo->model, "Model file (default: the shipped kriging model)");
    w->add_option("--base", wo->baseFile, "Base formulation TOML (mu_s, mu_d, i0, d [m], rho [kg/m3])");
    wo->base.add(w, "", "base: ", true);
    w->add_option("--new", wo->newFile, "New formulation TOML; default: the base with --new-* and --change applied");
    wo->changed.add(w, "new-", "new: ", true);
    w->add_option("--change", wo->changes, "Relative change of the new formulation, e.g. rho=+50% or mu_s=-10% (repeatable)");
    w->add_option("--feed-kg-h", wo->feed, "Operating point: feed [kg/h]");
    w->add_option("--rpm", wo->rpm, "Operating point: impeller speed [rpm]");
    w->add_option("--at", wo->at, "More operating points as FEED_KG_H:RPM (repeatable)");
    w->add_option("--report", wo->report,
                  "Write the what-if over the operating map (--feeds x --rpms) to this directory: report.md, report.csv, report.png");
    w->add_option("--feeds", wo->feeds, "Feeds of the report's map [kg/h]")->delimiter(',')->capture_default_str();
    w->add_option("--rpms", wo->rpms, "Speeds of the report's map [rpm]")->delimiter(',')->capture_default_str();
    w->add_flag("--extrapolate", wo->extrapolate,
                "Answer even far outside the training box (by default refused beyond 25% of an input's trained range; --report marks such points instead)");
    w->add_flag("--json", wo->json, "Print JSON");
    w->callback([&action, wo] { action = [wo] { return whatif(*wo); }; });
}

}  // namespace mixload::app
