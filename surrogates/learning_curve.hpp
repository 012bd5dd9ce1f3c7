// SPDX-License-Identifier: GPL-3.0-or-later
// Error against the number of training runs: the same model refitted on the first n training runs
// (in design order) for growing n, each checked on one fixed hold-out set, so that a campaign can
// say how many runs a target error needs.
#pragma once
#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "model.hpp"

namespace mixload::surrogates {

struct CurvePoint {
    int n = 0;
    double mean = 0, lo = 0, hi = 0;  // hold-out mean relative error and its 90% bootstrap interval
    double max = 0, coverage = 0;     // hold-out max relative error, 95% coverage
    double looMean = 0;               // leave-one-out mean relative error on the n runs
};

// sizes: training-set sizes, each at least 5 and at most train.size(). Throws InputError otherwise.
std::vector<CurvePoint> learningCurve(const std::vector<Row>& train, const std::vector<Row>& holdout, const FitOptions& o,
                                      const std::vector<int>& sizes);

// The power law mean error = c n^-p fitted to the curve in log-log (least squares), and the n at
// which it reaches `target` (an extrapolation, reported as one). Needs two sizes or more.
nlohmann::json powerLawOf(const std::vector<CurvePoint>& curve, double target);

// curve.md, curve.csv and curve.png (log-log, with the intervals and the power law) in dir.
nlohmann::json writeLearningCurve(const std::vector<CurvePoint>& curve, const nlohmann::json& law, const std::string& label,
                                  const std::filesystem::path& dir);

}  // namespace mixload::surrogates
