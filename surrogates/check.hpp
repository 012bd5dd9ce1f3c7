// SPDX-License-Identifier: GPL-3.0-or-later
// Checks a surrogate against full runs: every run it was not trained on (hold-out) is predicted;
// the runs it was trained on are judged by their leave-one-out predictions.
#pragma once
#include <nlohmann/json.hpp>

#include "model.hpp"
#include "table.hpp"

namespace mixload::surrogates {

// {"n_holdout", "mean_rel_error", "max_rel_error", "coverage95", "holdout": [...],
//  "loo": {"n", "mean_rel_error", "max_rel_error", "coverage95", "runs": [...]}}; errors are null
// without runs. Each run: id, inputs, loading_kg, predicted_kg (leave-one-out for training runs),
// ci95_kg, in_ci95 (null without an interval), rel_error, and for hold-out runs in_training_box.
nlohmann::json checkModel(const Surrogate& model, const Table& runs);

}  // namespace mixload::surrogates
