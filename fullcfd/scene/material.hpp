// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace mixload::scene {

// A powder: grain properties and mu(I) coefficients (standard convention unless a scene says
// otherwise). Bulk density = solid_fraction * grain_density.
struct Material {
    std::string name;
    double grainDensity = 0;  // rhoS [kg/m3]
    double grainDiameter = 0; // d [m]
    double solidFraction = 0; // phi [-]
    double muS = 0, muD = 0, I0 = 0;

    double bulkDensity() const { return solidFraction * grainDensity; }
    void validate() const;  // throws InputError naming the key
    nlohmann::json toJson() const;
};

// A shipped material by name (data/materials/<name>.toml) or a TOML file path.
Material loadMaterial(const std::string& nameOrPath);
Material parseMaterialToml(const std::string& text, const std::string& origin);
std::filesystem::path dataDir();

}  // namespace mixload::scene
