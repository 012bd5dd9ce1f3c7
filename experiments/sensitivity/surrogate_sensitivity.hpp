// SPDX-License-Identifier: GPL-3.0-or-later
// Which inputs the loading depends on, over a box of inputs: Sobol indices of a surrogate's M,
// written as a table and a bar chart.
#pragma once
#include <filesystem>

#include <nlohmann/json.hpp>

#include "doe/parameter_space.hpp"
#include "model.hpp"

namespace mixload::experiments {

// The box's parameters (mu_s, delta_mu, i0, d, rho, feed_kg_h, rpm; mu_d = mu_s + delta_mu) vary
// over their ranges (log-scaled ones evenly in the log); the surrogate's other inputs stay at
// `fixed`. n base samples, bootstrap resamples. Writes sensitivity.md, .csv and .png in outDir
// (each to a temporary name, then renamed) and returns the indices, the box and where the
// samples left the model's training box.
nlohmann::json surrogateSensitivity(const surrogates::Surrogate& model, const ParameterSpace& box,
                                    const surrogates::Point& fixed, int n, int bootstrap,
                                    const std::filesystem::path& outDir);

}  // namespace mixload::experiments
