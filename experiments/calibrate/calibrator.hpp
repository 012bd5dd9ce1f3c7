// SPDX-License-Identifier: GPL-3.0-or-later
// Bounded, derivative-free least-squares fit of a few parameters to targets (NLopt), for models
// whose every evaluation is expensive (a full run): it stops as soon as every target is well inside
// its band, and it is deterministic, so a driver that caches its evaluations can resume by simply
// running it again.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace mixload::experiments {

struct CalibrationBound {
    std::string key;
    double lo = 0, hi = 1;
    double start = 0.5;  // first point, inside [lo, hi]
    // Searched in log(x): for a parameter spanning decades (a viscosity cap), equal steps in the
    // search are equal factors, not equal increments. Needs lo > 0.
    bool log = false;
};

// "TABLE.KEY=LO:HI[:START][:log]" (or "KEY=..." when dotted is false); start: the middle (the
// geometric middle for log). Throws InputError naming the key.
CalibrationBound parseCalibrationParam(const std::string& text, bool dotted = true);

// Shared by the fits' text parsers: "a:b:c" -> {a, b, c}; a finite number or InputError(field, whole).
std::vector<std::string> splitColons(const std::string& s);
double parseFieldNumber(const std::string& field, const std::string& text, const std::string& whole);

struct CalibrationOptions {
    int maxEvals = 12;
    // Stop once the root mean square of the scaled residuals is at most this (1 = the edge of the
    // targets' bands).
    double stopRms = 0.25;
    // Stop once a step moves every parameter by less than this share of its range.
    double xtolShare = 0.005;
    // Residuals per evaluation, when known: one parameter against one target is a root search
    // (bracketing, then Illinois regula falsi); anything else goes to NLopt's BOBYQA.
    int residuals = 0;
};

struct CalibrationTrace {
    std::vector<std::vector<double>> x;  // parameters of each evaluation, in physical units
    std::vector<std::vector<double>> r;  // scaled residuals of each evaluation
    std::vector<double> rms;
    size_t best = 0;
    std::string stop;  // within-stop-rms | xtol | max-evals | bound (root search: target out of range) | ...
};

// residuals(x) returns, per target, (value - target) / (tolerance * target). Exceptions thrown by
// it end the fit and propagate (after the trace so far is handed to onEval).
using ResidualFn = std::function<std::vector<double>(const std::vector<double>&)>;
CalibrationTrace calibrate(const std::vector<CalibrationBound>& bounds, const ResidualFn& residuals,
                           const CalibrationOptions& opt,
                           const std::function<void(const CalibrationTrace&)>& onEval = {});

}  // namespace mixload::experiments
