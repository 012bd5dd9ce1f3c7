// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/point_options.hpp"

#include "common/input_error.hpp"
#include "table.hpp"

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
                             std::string("a value in ") + surrogates::kInputSpecs[k].unit);
        x[k] = *v[k];
    }
    surrogates::requirePhysical(x);
    return x;
}

}  // namespace mixload::app
