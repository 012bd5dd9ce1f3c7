// SPDX-License-Identifier: GPL-3.0-or-later
// The users' question answered from a fitted surrogate: M for a formulation, and how M changes
// from one formulation to another at given operating points, with each changed input's share.
#pragma once
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "model.hpp"

namespace mixload::experiments {

// The formulation's inputs among the surrogate's: mu_s, mu_d, i0, d, rho.
inline constexpr std::array<size_t, 5> kMaterial{0, 1, 2, 3, 4};

// One prediction as `predict --json` prints it: loading, 95% interval, whether the point lies in
// the training box (and where not), the model and what it was trained on.
// The regime of x (surrogates/regime.hpp) and the model's measured hold-out error in it, from the
// latest check in its history with per-regime figures: {"name", "measured": {n_holdout,
// mean_rel_error, ..., date_utc, source} or null}; and that as one line for a person.
nlohmann::json regimeErrorJson(const surrogates::Surrogate& m, const surrogates::Point& x);
std::string regimeErrorLine(const nlohmann::json& regime);

nlohmann::json predictionJson(const surrogates::Surrogate& m, const surrogates::Point& x,
                              const surrogates::Prediction& p, const std::string& modelPath);

// For each (feed kg/h, rpm): both predictions, dM, dM/M, its 95% interval (from the two
// predictions' joint distribution, Surrogate::predictDifference), each changed input's effect alone from the base, and the interaction left.
// Throws InputError for a point outside the physical ranges, and (unless extrapolate) for one
// farther from the training box than Surrogate::requireNearBox allows; nothing is predicted then.
nlohmann::json compareFormulations(const surrogates::Surrogate& m, const std::string& modelPath,
                                   const surrogates::Point& base, const surrogates::Point& changed,
                                   const std::vector<std::pair<double, double>>& operatingPoints, bool extrapolate = true);

// The what-if over an operating map: compareFormulations at every (feed, rpm) of the grid, written
// to dir as report.md, report.csv and report.png (M of both formulations with their intervals, and
// dM with its interval, against the feed, one line per speed), each to a temporary name and
// renamed. Returns the points as compareFormulations does, and the files.
nlohmann::json whatifReport(const surrogates::Surrogate& m, const std::string& modelPath, const surrogates::Point& base,
                            const surrogates::Point& changed, const std::vector<double>& feeds, const std::vector<double>& rpms,
                            const std::filesystem::path& dir);

}  // namespace mixload::experiments
