// SPDX-License-Identifier: GPL-3.0-or-later
// Checks a surrogate against full runs: every run it was not trained on (hold-out) is predicted;
// the runs it was trained on are judged by their leave-one-out predictions.
#pragma once
#include <nlohmann/json.hpp>

#include "model.hpp"
#include "table.hpp"

namespace mixload::surrogates {

// {"n_holdout", "mean_rel_error", "max_rel_error", "coverage95", "holdout": [...],
//  "loo": {"n", "mean_rel_error", "max_rel_error", "coverage95"}}; errors are null without runs.
nlohmann::json checkModel(const Surrogate& model, const Table& runs);

}  // namespace mixload::surrogates
