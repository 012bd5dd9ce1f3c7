// SPDX-License-Identifier: GPL-3.0-or-later
#include "check.hpp"

#include <cmath>
#include <set>

#include "error_stats.hpp"

namespace mixload::surrogates {

nlohmann::json checkModel(const Surrogate& model, const Table& runs) {
    const std::set<std::string> trained(model.trainingIds().begin(), model.trainingIds().end());
    ErrorStats hold, inBox, loo;
    nlohmann::json list = nlohmann::json::array();
    auto ws = model.makeWorkspace();
    for (const auto& r : runs.rows) {
        if (trained.count(r.id)) {
            if (model.loo().contains(r.id)) {
                const auto& l = model.loo()[r.id];
                loo.add(r.m, l[0], l[1].is_null() ? NAN : l[1].get<double>(), l[2].is_null() ? NAN : l[2].get<double>());
            }
            continue;
        }
        const auto p = model.predict(r.x, ws);
        hold.add(r.m, p.m, p.lo, p.hi);
        if (p.inBox) inBox.add(r.m, p.m, p.lo, p.hi);
        list.push_back({{"id", r.id},
                        {"loading_kg", r.m},
                        {"predicted_kg", p.m},
                        {"ci95_kg", {p.lo, p.hi}},
                        {"rel_error", std::abs(p.m - r.m) / std::abs(r.m)},
                        {"in_training_box", p.inBox}});
    }
    return {{"n_holdout", hold.n},
            {"mean_rel_error", hold.mean()},
            {"mean_rel_error_ci90", hold.meanInterval90()},
            {"max_rel_error", hold.maxJson()},
            {"coverage95", hold.coverage()},
            {"holdout", list},
            // Outside the box a model extrapolates; its error there says little about its use inside.
            {"holdout_in_box",
             {{"n", inBox.n},
              {"mean_rel_error", inBox.mean()},
              {"mean_rel_error_ci90", inBox.meanInterval90()},
              {"max_rel_error", inBox.maxJson()},
              {"coverage95", inBox.coverage()}}},
            {"loo",
             {{"n", loo.n},
              {"mean_rel_error", loo.mean()},
              {"mean_rel_error_ci90", loo.meanInterval90()},
              {"max_rel_error", loo.maxJson()},
              {"coverage95", loo.coverage()}}}};
}

}  // namespace mixload::surrogates
