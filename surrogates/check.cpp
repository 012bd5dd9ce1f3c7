// SPDX-License-Identifier: GPL-3.0-or-later
#include "check.hpp"

#include <algorithm>
#include <cmath>
#include <set>

namespace mixload::surrogates {

namespace {
struct Stats {
    size_t n = 0, covered = 0, withInterval = 0;
    double sum = 0, max = 0;
    void add(double m, double pred, double lo, double hi) {
        const double e = std::abs(pred - m) / std::abs(m);
        ++n;
        sum += e;
        max = std::max(max, e);
        if (!std::isnan(lo) && !std::isnan(hi)) {
            ++withInterval;
            covered += m >= lo && m <= hi;
        }
    }
    nlohmann::json mean() const { return n ? nlohmann::json(sum / static_cast<double>(n)) : nlohmann::json(); }
    nlohmann::json maxJson() const { return n ? nlohmann::json(max) : nlohmann::json(); }
    nlohmann::json coverage() const {
        return withInterval ? nlohmann::json(static_cast<double>(covered) / static_cast<double>(withInterval))
                            : nlohmann::json();
    }
};
}  // namespace

nlohmann::json checkModel(const Surrogate& model, const Table& runs) {
    const std::set<std::string> trained(model.trainingIds().begin(), model.trainingIds().end());
    Stats hold, loo;
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
        list.push_back({{"id", r.id},
                        {"loading_kg", r.m},
                        {"predicted_kg", p.m},
                        {"ci95_kg", {p.lo, p.hi}},
                        {"rel_error", std::abs(p.m - r.m) / std::abs(r.m)},
                        {"in_training_box", p.inBox}});
    }
    return {{"n_holdout", hold.n},
            {"mean_rel_error", hold.mean()},
            {"max_rel_error", hold.maxJson()},
            {"coverage95", hold.coverage()},
            {"holdout", list},
            {"loo",
             {{"n", loo.n}, {"mean_rel_error", loo.mean()}, {"max_rel_error", loo.maxJson()}, {"coverage95", loo.coverage()}}}};
}

}  // namespace mixload::surrogates
