// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/point_options.hpp"

#include "common/input_error.hpp"
#include "table.hpp"
#include "whatif/whatif.hpp"

namespace mixload::app {

std::string defaultModelPath() { return std::string(MIXLOAD_DATA_DIR) + "/models/mixer-loading-kriging.json"; }

void PointOptions::add(CLI::App* cmd, const std::string& prefix, const std::string& what, bool materialOnly) {
    static const std::array<const char*, surrogates::kInputs> help{
        "static friction coefficient mu_s [-]",
        "dynamic friction coefficient mu_d [-] (> mu_s)",
        "I0 of the mu(I) law [-]",
        "grain diameter d [m] (SI: 240e-6 for 240 um)",
        "bulk density rho [kg/m3]",
        "powder feed rate [kg/h]",
        "impeller speed [rpm]"};
    for (size_t k = 0; k < (materialOnly ? 5u : surrogates::kInputs); ++k) {
        const std::string flag = std::string("--") + prefix + (surrogates::kInputSpecs[k].flag + 2);
        cmd->add_option(flag, v[k], what + help[k]);
    }
}

surrogates::Point PointOptions::point(const std::string& prefix) const {
    surrogates::Point x{};
    for (size_t k = 0; k < surrogates::kInputs; ++k) {
        if (!v[k])
            throw InputError(std::string("--") + prefix + (surrogates::kInputSpecs[k].flag + 2), "(missing)",
                             missingInputHint(k));
        x[k] = *v[k];
    }
    surrogates::requirePhysical(x);
    return x;
}

namespace {
// The paper's reference point: Avicel (its Table 4) at 5 kg/h and 39 rpm.
constexpr surrogates::Point kPaperReference{0.31, 0.44, 0.28, 240e-6, 329.84, 5.0, 39.0};
}  // namespace

std::string missingInputHint(size_t k) {
    const std::string unit = surrogates::kInputSpecs[k].unit;
    return "a number " + (unit == "1" ? std::string("(dimensionless)") : "[" + unit + "]") + ", e.g. " +
           formatNumber(kPaperReference[k]) + " (the paper's Avicel at 5 kg/h, 39 rpm)";
}

surrogates::Point PointOptions::orPaperReference() const {
    surrogates::Point x{};
    for (size_t k = 0; k < surrogates::kInputs; ++k) x[k] = v[k] ? *v[k] : kPaperReference[k];
    surrogates::requirePhysical(x);
    return x;
}

void applyChange(surrogates::Point& x, const std::string& c, const std::string& field) {
    const char* allowed = "NAME=+X% or NAME=-X% with NAME one of mu_s, mu_d, i0, d, rho";
    const auto eq = c.find('=');
    const std::string name = c.substr(0, eq);
    std::string v = eq == std::string::npos ? "" : c.substr(eq + 1);
    size_t k = surrogates::kInputs;
    for (size_t i : experiments::kMaterial)
        if (name == surrogates::kInputSpecs[i].name) k = i;
    if (k == surrogates::kInputs || v.empty() || v.back() != '%') throw InputError(field, c, allowed);
    v.pop_back();
    try {
        size_t used = 0;
        const double pc = std::stod(v, &used);
        if (used != v.size()) throw std::invalid_argument(v);
        x[k] *= 1 + pc / 100;
    } catch (const std::exception&) {
        throw InputError(field, c, allowed);
    }
}

}  // namespace mixload::app
