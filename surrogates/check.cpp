// SPDX-License-Identifier: GPL-3.0-or-later
#include "check.hpp"

#include <array>
#include <cmath>
#include <set>

#include "error_stats.hpp"
#include "regime.hpp"

namespace mixload::surrogates {

nlohmann::json checkModel(const Surrogate& model, const Table& runs) {
    const std::set<std::string> trained(model.trainingIds().begin(), model.trainingIds().end());
    ErrorStats hold, inBox, loo;
    // The same statistics per flow regime (surrogates/regime.hpp): a model can be good on beds and
    // poor across the transition, and one mean hides it (issue 64's targets are per regime).
    std::array<ErrorStats, 3> holdBy, looBy;
    nlohmann::json list = nlohmann::json::array();
    auto ws = model.makeWorkspace();
    nlohmann::json looList = nlohmann::json::array();
    // One entry per run, with its inputs, so that a user sees which runs a model misses.
    const auto entry = [](const Row& r, double m, double lo, double hi) {
        const auto in95 = covers(r.m, lo, hi);
        nlohmann::json in;
        for (int k = 0; k < kInputs; ++k) in[kInputSpecs[k].name] = r.x[k];
        return nlohmann::json{{"id", r.id},
                              {"inputs", in},
                              {"loading_kg", r.m},
                              {"predicted_kg", m},
                              {"ci95_kg", {lo, hi}},
                              {"in_ci95", in95 ? nlohmann::json(*in95) : nlohmann::json()},
                              {"rel_error", std::abs(m - r.m) / std::abs(r.m)}};
    };
    for (const auto& r : runs.rows) {
        if (trained.count(r.id)) {
            if (model.loo().contains(r.id)) {
                const auto& l = model.loo()[r.id];
                const double lo = l[1].is_null() ? NAN : l[1].get<double>(), hi = l[2].is_null() ? NAN : l[2].get<double>();
                loo.add(r.m, l[0], lo, hi);
                looBy[static_cast<int>(regimeOf(r.x))].add(r.m, l[0], lo, hi);
                looList.push_back(entry(r, l[0], lo, hi));
            }
            continue;
        }
        const auto p = model.predict(r.x, ws);
        hold.add(r.m, p.m, p.lo, p.hi);
        holdBy[static_cast<int>(regimeOf(r.x))].add(r.m, p.m, p.lo, p.hi);
        if (p.inBox) inBox.add(r.m, p.m, p.lo, p.hi);
        auto e = entry(r, p.m, p.lo, p.hi);
        e["in_training_box"] = p.inBox;
        list.push_back(std::move(e));
    }
    const auto byRegime = [](const std::array<ErrorStats, 3>& by) {
        nlohmann::json j = nlohmann::json::object();
        for (int k = 0; k < 3; ++k)
            j[regimeName(static_cast<Regime>(k))] = {{"n", by[k].n},
                                                     {"mean_rel_error", by[k].mean()},
                                                     {"mean_rel_error_ci90", by[k].meanInterval90()},
                                                     {"max_rel_error", by[k].maxJson()},
                                                     {"coverage95", by[k].coverage()}};
        return j;
    };
    return {{"n_holdout", hold.n},
            {"holdout_by_regime", byRegime(holdBy)},
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
              {"coverage95", loo.coverage()},
              {"by_regime", byRegime(looBy)},
              {"runs", looList}}}};
}

}  // namespace mixload::surrogates
