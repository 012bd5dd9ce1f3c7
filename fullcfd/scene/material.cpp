// SPDX-License-Identifier: GPL-3.0-or-later
#include "scene/material.hpp"

#include <cstdlib>
#include <toml++/toml.h>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"

namespace mixload::scene {

std::filesystem::path dataDir() {
    if (const char* env = std::getenv("MIXLOAD_DATA_DIR")) return env;
    return MIXLOAD_DATA_DIR;
}

void Material::validate() const {
    requireRange("grain_density_kg_m3", grainDensity, 0.0, 25000.0, false, true);
    requireRange("grain_diameter_m", grainDiameter, 0.0, 0.01, false, true);
    requireRange("solid_fraction", solidFraction, 0.0, 0.74, false, true);
    requireRange("mu_s", muS, 0.0, 3.0, false, true);
    requireRange("mu_d", muD, muS, 5.0, false, true);  // mu_d > mu_s: friction grows with I
    requireRange("i0", I0, 0.0, 10.0, false, true);
}

nlohmann::json Material::toJson() const {
    return {{"name", name},
            {"grain_density_kg_m3", grainDensity},
            {"grain_diameter_m", grainDiameter},
            {"solid_fraction", solidFraction},
            {"bulk_density_kg_m3", bulkDensity()},
            {"mu_s", muS},
            {"mu_d", muD},
            {"i0", I0}};
}

namespace {
double requireNumber(const toml::table& t, const std::string& key, const std::string& origin) {
    const auto node = t[key];
    if (!node) throw InputError(origin + ": missing key " + key);
    if (auto v = node.value<double>()) return *v;
    throw InputError(key, "<not a number>", "a number (in " + origin + ")");
}
}  // namespace

Material parseMaterialToml(const std::string& text, const std::string& origin) {
    toml::table t;
    try {
        t = toml::parse(text, origin);
    } catch (const toml::parse_error& e) {
        const auto& src = e.source();
        throw InputError(origin + ":" + std::to_string(src.begin.line) + ":" +
                         std::to_string(src.begin.column) + ": malformed TOML: " +
                         std::string(e.description()));
    }
    static const char* known[] = {"name", "grain_density_kg_m3", "grain_diameter_m",
                                  "solid_fraction", "mu_s", "mu_d", "i0"};
    for (const auto& [k, v] : t) {
        bool ok = false;
        for (const char* n : known) ok = ok || k.str() == n;
        if (!ok) throw InputError(origin + ": unknown key " + std::string(k.str()));
    }
    Material m;
    m.name = t["name"].value_or(std::filesystem::path(origin).stem().string());
    m.grainDensity = requireNumber(t, "grain_density_kg_m3", origin);
    m.grainDiameter = requireNumber(t, "grain_diameter_m", origin);
    m.solidFraction = requireNumber(t, "solid_fraction", origin);
    m.muS = requireNumber(t, "mu_s", origin);
    m.muD = requireNumber(t, "mu_d", origin);
    m.I0 = requireNumber(t, "i0", origin);
    m.validate();
    return m;
}

Material loadMaterial(const std::string& nameOrPath) {
    std::filesystem::path p(nameOrPath);
    if (p.extension() != ".toml") {
        const auto shipped = dataDir() / "materials" / (nameOrPath + ".toml");
        if (!std::filesystem::exists(shipped)) {
            std::string names;
            for (const auto& e : std::filesystem::directory_iterator(dataDir() / "materials"))
                if (e.path().extension() == ".toml")
                    names += (names.empty() ? "" : "|") + e.path().stem().string();
            throw InputError("material", nameOrPath, names + " or a .toml file");
        }
        p = shipped;
    }
    if (!std::filesystem::exists(p)) throw InputError("material", nameOrPath, "an existing .toml file");
    return parseMaterialToml(readFile(p), p.string());
}

}  // namespace mixload::scene
