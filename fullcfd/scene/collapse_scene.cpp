// SPDX-License-Identifier: GPL-3.0-or-later
#include "scene/collapse_scene.hpp"

#include <cmath>

#include "common/hash.hpp"
#include "common/input_error.hpp"
#include "muILaw.H"

namespace mixload::scene {

double runoutEstimate(double a) { return a < 3.0 ? 1.2 * a : 1.9 * std::pow(a, 2.0 / 3.0); }

void CollapseScene::validate() const {
    material.validate();
    requireRange("aspect", aspect, 0.2, 10.0);
    requireRange("length", length, 0.0, 1.0, false, true);
    requireRange("cells-per-length", cellsPerLength, 4, 200);
    if (rheology != "muI" && rheology != "muIRegularised" && rheology != "schaeffer")
        throw InputError("rheology", rheology, "muI|muIRegularised|schaeffer");
    if (convention != "standard" && convention != "paper")
        throw InputError("convention", convention, "standard|paper");
    if (etaMax) requirePositive("eta-max", *etaMax);
    requireRange("cap-h-ratio", capHeightRatio, 1e-3, 1e6);
    if (etaMax && capHeightRatio != 1.0)
        throw InputError("cap-h-ratio", formatNumber(capHeightRatio), "1 with --eta-max (one or the other)");
    requirePositive("p-min", pMin);
    requireRange("writes-per-tstar", writesPerTstar, 1, 200);
    requireRange("rest-fraction", restFraction, 0.0, 0.5, false, true);
    requireRange("rest-time", restTimeTstar, 0.0, 10.0, false, true);
    requireRange("cap", capTstar, 1.0, 200.0);
    requireRange("max-courant", maxCourant, 0.01, 5.0);
    if (cells() > 5'000'000)
        throw InputError("cells-per-length", std::to_string(cellsPerLength),
                         "a mesh of at most 5e6 cells (this one has " + std::to_string(cells()) + ")");
}

double CollapseScene::etaMaxValue() const {
    return etaMax ? *etaMax
                  : rheology::rauterEtaMax(material.grainDensity, gravity, capHeightRatio * height());
}

double CollapseScene::muSCase() const {
    return convention == "paper" ? material.muS / std::sqrt(2.0) : material.muS;
}
double CollapseScene::muDCase() const {
    return convention == "paper" ? material.muD / std::sqrt(2.0) : material.muD;
}

int CollapseScene::nx() const {
    // Column + 60% margin on the estimated runout + one column length of air.
    const double width = length * (2.0 + 1.6 * runoutEstimate(aspect));
    return static_cast<int>(std::ceil(width / dx() - 1e-9));
}

int CollapseScene::ny() const {
    // Powder never rises above the initial column; 10% + 2 cells of air above it.
    return static_cast<int>(std::ceil(1.1 * height() / dx() - 1e-9)) + 2;
}

nlohmann::json CollapseScene::toJson() const {
    nlohmann::json j{{"scene", "collapse2d"},
            {"material", material.toJson()},
            {"aspect", aspect},
            {"length_m", length},
            {"cells_per_length", cellsPerLength},
            {"rheology", rheology},
            {"convention", convention},
            {"eta_max_pa_s", etaMaxValue()},
            {"p_min_pa", pMin},
            {"gravity_m_s2", gravity},
            {"rest_fraction", restFraction},
            {"rest_time_tstar", restTimeTstar},
            {"cap_tstar", capTstar}};
    // Only a non-default limit enters the record, so hashes of existing runs stay valid.
    if (maxCourant != CollapseScene{}.maxCourant) j["max_courant"] = maxCourant;
    if (writesPerTstar != CollapseScene{}.writesPerTstar) j["writes_per_tstar"] = writesPerTstar;
    return j;
}

std::string CollapseScene::hash() const { return stableHash(toJson().dump()); }

}  // namespace mixload::scene
