// SPDX-License-Identifier: GPL-3.0-or-later
// Relative errors of predictions against full runs, and how often the runs fall inside the
// predicted 95% intervals: what validation at fit time and `mixload check` both report.
#pragma once
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/stats.hpp"

namespace mixload::surrogates {

// Whether a run's loading m lies in a predicted interval; nothing without one (NaN bounds). One
// rule for the coverage figures and for each checked run's entry.
inline std::optional<bool> covers(double m, double lo, double hi) {
    if (std::isnan(lo) || std::isnan(hi)) return std::nullopt;
    return m >= lo && m <= hi;
}

struct ErrorStats {
    std::size_t n = 0, covered = 0, withInterval = 0;
    double sum = 0, max = 0;
    std::vector<double> errors;

    // A run's loading m against a prediction and its interval (NaN bounds: no interval).
    void add(double m, double pred, double lo, double hi) {
        const double e = std::abs(pred - m) / std::abs(m);
        ++n;
        errors.push_back(e);
        sum += e;
        max = std::max(max, e);
        if (const auto c = covers(m, lo, hi)) {
            ++withInterval;
            covered += *c;
        }
    }
    // null when there is nothing to report
    nlohmann::json mean() const { return n ? nlohmann::json(sum / static_cast<double>(n)) : nlohmann::json(); }
    nlohmann::json maxJson() const { return n ? nlohmann::json(max) : nlohmann::json(); }
    // 90% bootstrap interval of the mean relative error. With a few dozen runs and heavy tails the
    // mean alone cannot tell two models apart; the interval says whether it can.
    nlohmann::json meanInterval90() const {
        if (n < 2) return nlohmann::json();
        const auto ci = bootstrapMeanInterval90(errors);
        return nlohmann::json::array({ci[0], ci[1]});
    }
    nlohmann::json coverage() const {
        return withInterval ? nlohmann::json(static_cast<double>(covered) / static_cast<double>(withInterval))
                            : nlohmann::json();
    }
};

}  // namespace mixload::surrogates
