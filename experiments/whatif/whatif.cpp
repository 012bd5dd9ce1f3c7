// SPDX-License-Identifier: GPL-3.0-or-later
#include "whatif/whatif.hpp"

#include <cmath>

namespace mixload::experiments {

using surrogates::kInputSpecs;
using surrogates::Point;

nlohmann::json predictionJson(const surrogates::Surrogate& m, const surrogates::Point& x, const surrogates::Prediction& p,
                              const std::string& modelPath) {
    nlohmann::json j{{"loading_kg", p.m},
                     {"ci95_kg", std::isnan(p.lo) ? nlohmann::json() : nlohmann::json{p.lo, p.hi}},
                     {"in_training_box", p.inBox},
                     {"model", modelPath},
                     {"kind", m.kind()},
                     {"source", m.sourceLabel()}};
    if (!p.inBox) j["outside"] = m.outsideBox(x);
    return j;
}

nlohmann::json compareFormulations(const surrogates::Surrogate& m, const std::string& modelPath, const Point& base,
                                   const Point& changed, const std::vector<std::pair<double, double>>& operatingPoints) {
    auto ws = m.makeWorkspace();
    nlohmann::json points = nlohmann::json::array();
    for (const auto& [feed, rpm] : operatingPoints) {
        Point xa = base, xb = changed;
        xa[5] = xb[5] = feed;
        xa[6] = xb[6] = rpm;
        surrogates::requirePhysical(xa);
        surrogates::requirePhysical(xb);
        const auto pa = m.predict(xa, ws), pb = m.predict(xb, ws);
        // The two predictions share most of their error: the interval of the difference comes
        // from their joint distribution (the independent one beside it, for comparison).
        const auto diff = m.predictDifference(xa, xb);
        const double dm = pb.m - pa.m;
        nlohmann::json attribution = nlohmann::json::array();
        double sum = 0;
        for (size_t k : kMaterial) {
            if (xa[k] == xb[k]) continue;
            Point xk = xa;
            xk[k] = xb[k];
            const double dk = m.predict(xk, ws).m - pa.m;  // this input alone, from the base
            sum += dk;
            attribution.push_back({{"input", kInputSpecs[k].name}, {"from", xa[k]}, {"to", xb[k]}, {"delta_kg", dk}});
        }
        points.push_back({{"feed_kg_h", feed},
                                 {"rpm", rpm},
                                 {"base", predictionJson(m, xa, pa, modelPath)},
                                 {"new", predictionJson(m, xb, pb, modelPath)},
                                 {"delta_kg", dm},
                                 {"delta_rel", dm / pa.m},
                                 {"delta_ci95_kg", std::isnan(diff.lo) ? nlohmann::json() : nlohmann::json{diff.lo, diff.hi}},
                                 {"delta_ci95_independent_kg",
                                  std::isnan(diff.lo) ? nlohmann::json() : nlohmann::json{diff.loIndependent, diff.hiIndependent}},
                                 {"error_correlation", diff.correlation},
                                 {"attribution", attribution},
                                 {"interaction_kg", dm - sum}});
    }
    return points;
}

}  // namespace mixload::experiments
