// SPDX-License-Identifier: GPL-3.0-or-later
// What a collapse calibration fits to: final runouts and heights against the aspect ratio, with
// their uncertainties, read from a CSV file of measurements or generated from a published scaling
// law (data/collapse-laws/<name>.toml, which carries its citation).
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mixload::experiments {

struct CollapseMeasurement {
    double aspect = 0;                      // a = Hi / Li
    std::optional<double> runout, runoutSd; // L*f = (Lf - Li) / Li and its standard uncertainty
    std::optional<double> height, heightSd; // H*f = Hf / Hi and its standard uncertainty
};

struct CollapseData {
    std::string source;  // the file, or the law's name and citation
    std::vector<CollapseMeasurement> points;
    nlohmann::json toJson() const;
};

// CSV with the header aspect,runout_star,runout_sd,height_star,height_sd (either pair may be left
// empty on a row, not both); '#' starts a comment line; the first comment is kept as the source.
// Throws InputError naming the file, line and field.
CollapseData readCollapseData(const std::filesystem::path& file);
CollapseData parseCollapseData(const std::string& text, const std::string& origin);

// A piecewise power law y = c a^e, each piece over [a_min, a_max]; between pieces (a transition
// the authors fit no law to) the law has no value. One for the runout L*f, one (optional) for
// the final height H*f.
struct PowerPiece {
    double aMin = 0, aMax = 0, c = 0, e = 0;
};
struct CollapseLaw {
    std::string name, citation, material, geometry, provenance;
    std::vector<PowerPiece> runout, height;
    double runoutRelSd = 0.1, heightRelSd = 0.05;  // the scatter to weigh the law by
    static std::optional<double> value(const std::vector<PowerPiece>& law, double a);
    std::string regimes() const;  // "[0.5, 1.8] or [2.8, 10]": where the runout law has a value
};

CollapseLaw loadCollapseLaw(const std::string& nameOrPath);  // shipped name or a .toml path
std::vector<std::string> shippedCollapseLaws();
// The law's values at these aspects (each inside one of its runout pieces, else InputError).
CollapseData collapseDataFromLaw(const CollapseLaw& law, const std::vector<double>& aspects);

}  // namespace mixload::experiments
