// SPDX-License-Identifier: GPL-3.0-or-later
// The input box of a design of experiments, read from a TOML ranges file:
//
//   scene = "mixer"                       # mixer | collapse
//   [mu_s]     min = 0.20  max = 0.45  unit = "1"
//   [delta_mu] min = 0.05  max = 0.30  unit = "1"   # mu_d = mu_s + delta_mu > mu_s always
//   [d]        min = 100e-6 max = 400e-6 unit = "m"
//   [feed_kg_h] min = 2.5 max = 65 unit = "kg/h" scale = "log"   # optional: linear (default) | log
//
// Each parameter is a table with min < max and its unit spelled exactly as below, so a file written
// in micrometres or g/cm3 is refused instead of silently misread. mu_d is never sampled: sampling
// delta_mu > 0 keeps mu_d > mu_s for every point without rejecting any.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

namespace mixload::experiments {

struct Parameter {
    std::string name, unit;
    double min = 0, max = 0;
    bool log = false;  // scale = "log": the unit interval maps to log(min) .. log(max)
};

struct ParameterSpace {
    std::string scene;              // mixer | collapse
    std::vector<Parameter> params;  // sorted by name: a design column is always the same input

    // A point of the unit cube [0,1)^k mapped to the box (linearly, or in the log of a log-scaled
    // parameter).
    std::vector<double> toPhysical(const std::vector<double>& unit) const;
    // The inverse, for extending a design from its recorded physical points.
    std::vector<double> toUnit(const std::vector<double>& physical) const;
    const Parameter* find(const std::string& name) const;
};

// Throws InputError naming the parameter, the value and what is allowed; origin names the file.
ParameterSpace parseRanges(const std::string& text, const std::string& origin);
ParameterSpace loadRanges(const std::filesystem::path& file);

// The parameters a scene accepts, with their units, e.g. {"d", "m"}.
std::vector<std::pair<std::string, std::string>> knownParameters(const std::string& scene);

}  // namespace mixload::experiments
