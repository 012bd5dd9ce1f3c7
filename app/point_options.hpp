// SPDX-License-Identifier: GPL-3.0-or-later
// The seven surrogate inputs as command-line flags (SI units), and where the shipped model lives.
#pragma once
#include <array>
#include <optional>
#include <string>

#include <CLI/CLI.hpp>

#include "inputs.hpp"

namespace mixload::app {

// The shipped kriging model (regenerate: see README, Surrogates).
std::string defaultModelPath();

struct PointOptions {
    std::array<std::optional<double>, surrogates::kInputs> v;
    // prefix "" gives --mu-s ...; materialOnly: the five formulation inputs, not feed and rpm.
    void add(CLI::App* cmd, const std::string& prefix = "", const std::string& what = "", bool materialOnly = false);
    // Throws InputError naming a missing flag; checks the point is physical (mu_d > mu_s, ...).
    surrogates::Point point(const std::string& prefix = "") const;
    // The given values, the rest at the paper's reference point (Avicel, 5 kg/h, 39 rpm); checked
    // physical.
    surrogates::Point orPaperReference() const;
};

// What a missing input flag should hold, for its error message: its unit and the paper's reference
// value, e.g. "a number [kg/m3], e.g. 329.84 (the paper's Avicel at 5 kg/h, 39 rpm)".
std::string missingInputHint(size_t k);

// "rho=+50%" or "mu_s=-10%": a relative change of one formulation input, applied to x. Throws
// InputError (field `field`) for anything else.
void applyChange(surrogates::Point& x, const std::string& change, const std::string& field = "change");

}  // namespace mixload::app
