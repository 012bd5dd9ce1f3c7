// SPDX-License-Identifier: GPL-3.0-or-later
#include "doe/parameter_space.hpp"

#include <toml++/toml.h>

#include <cmath>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"

namespace mixload::experiments {

namespace {

struct Known {
    const char* name;
    const char* unit;
    double lo, hi;  // physically allowed values (open at 0 where zero is meaningless)
    bool loOpen;
};

// Mixer inputs in the units of `mixload mixer` (SI, feed in kg/h, speed in rev/min).
const std::vector<Known> kMixer = {
    {"mu_s", "1", 0, 2, true},       {"delta_mu", "1", 0, 2, true}, {"i0", "1", 0, 10, true},
    {"d", "m", 0, 0.01, true},       {"rho", "kg/m3", 0, 20000, true},
    {"feed_kg_h", "kg/h", 0, 1000, false}, {"rpm", "rpm", 0, 2000, false}};
const std::vector<Known> kCollapse = {{"mu_s", "1", 0, 2, true},
                                      {"delta_mu", "1", 0, 2, true},
                                      {"i0", "1", 0, 10, true},
                                      {"aspect", "1", 0, 50, true}};

const std::vector<Known>& table(const std::string& scene) {
    return scene == "collapse" ? kCollapse : kMixer;
}

std::string allowedNames(const std::string& scene) {
    std::string s;
    for (const auto& k : table(scene)) s += (s.empty() ? "" : "|") + std::string(k.name);
    return s;
}

}  // namespace

std::vector<std::pair<std::string, std::string>> knownParameters(const std::string& scene) {
    std::vector<std::pair<std::string, std::string>> out;
    for (const auto& k : table(scene)) out.emplace_back(k.name, k.unit);
    return out;
}

std::vector<double> ParameterSpace::toPhysical(const std::vector<double>& unit) const {
    std::vector<double> x(params.size());
    for (size_t j = 0; j < params.size(); ++j) {
        const auto& p = params[j];
        x[j] = p.log ? std::exp(std::log(p.min) + unit.at(j) * (std::log(p.max) - std::log(p.min)))
                     : p.min + unit.at(j) * (p.max - p.min);
    }
    return x;
}

std::vector<double> ParameterSpace::toUnit(const std::vector<double>& physical) const {
    std::vector<double> u(params.size());
    for (size_t j = 0; j < params.size(); ++j) {
        const auto& p = params[j];
        u[j] = p.log ? (std::log(physical.at(j)) - std::log(p.min)) / (std::log(p.max) - std::log(p.min))
                     : (physical.at(j) - p.min) / (p.max - p.min);
    }
    return u;
}

const Parameter* ParameterSpace::find(const std::string& name) const {
    for (const auto& p : params)
        if (p.name == name) return &p;
    return nullptr;
}

ParameterSpace parseRanges(const std::string& text, const std::string& origin) {
    toml::table t;
    try {
        t = toml::parse(text, origin);
    } catch (const toml::parse_error& e) {
        throw InputError("ranges", origin, std::string("valid TOML (") + std::string(e.description()) + ")");
    }
    ParameterSpace ps;
    ps.scene = t["scene"].value_or(std::string());
    if (ps.scene != "mixer" && ps.scene != "collapse")
        throw InputError("scene", ps.scene.empty() ? "(missing)" : ps.scene, "mixer|collapse");
    for (const auto& [key, node] : t) {
        const std::string name(key.str());
        if (name == "scene") continue;
        const Known* k = nullptr;
        for (const auto& c : table(ps.scene))
            if (name == c.name) k = &c;
        if (!k) throw InputError("parameter", name, allowedNames(ps.scene) + " for scene " + ps.scene);
        const auto* tab = node.as_table();
        if (!tab) throw InputError(name, "a value", "a table with min, max and unit");
        for (const auto& [field, _] : *tab)
            if (field.str() != "min" && field.str() != "max" && field.str() != "unit" && field.str() != "scale")
                throw InputError(name + "." + std::string(field.str()), "(unknown key)", "min|max|unit|scale");
        const auto unit = (*tab)["unit"].value<std::string>();
        if (!unit) throw InputError(name + ".unit", "(missing)", std::string("\"") + k->unit + "\"");
        if (*unit != k->unit) throw InputError(name + ".unit", *unit, std::string("\"") + k->unit + "\"");
        const auto lo = (*tab)["min"].value<double>(), hi = (*tab)["max"].value<double>();
        if (!lo) throw InputError(name + ".min", "(missing)", "a number");
        if (!hi) throw InputError(name + ".max", "(missing)", "a number");
        requireRange(name + ".min", *lo, k->lo, k->hi, !k->loOpen);
        requireRange(name + ".max", *hi, k->lo, k->hi, !k->loOpen);
        if (!(*lo < *hi)) throw InputError(name + ".min", formatNumber(*lo), "< max = " + formatNumber(*hi));
        // A range over a decade or more (the feed, the grain size) is sampled evenly in its log, so
        // the design does not crowd the top decade.
        const std::string scale = (*tab)["scale"].value_or(std::string("linear"));
        if (scale != "linear" && scale != "log") throw InputError(name + ".scale", scale, "linear|log");
        if (scale == "log" && !(*lo > 0)) throw InputError(name + ".min", formatNumber(*lo), "> 0 for scale = \"log\"");
        ps.params.push_back({name, *unit, *lo, *hi, scale == "log"});
    }
    if (ps.params.empty()) throw InputError("ranges", origin, "at least one parameter table");
    return ps;
}

ParameterSpace loadRanges(const std::filesystem::path& file) {
    if (!std::filesystem::exists(file)) throw InputError("ranges", file.string(), "an existing TOML file");
    return parseRanges(readFile(file), file.string());
}

}  // namespace mixload::experiments
