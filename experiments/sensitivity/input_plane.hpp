// SPDX-License-Identifier: GPL-3.0-or-later
// The loading over a plane of two inputs, the others held at a base point, from a surrogate: the
// paper's Fig. 8 (M over mu_s and rho, with its two what-if arrows), checked against the full runs
// that lie on the plane.
#pragma once
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model.hpp"
#include "table.hpp"

namespace mixload::experiments {

struct PlaneAxis {
    size_t input = 0;  // index into surrogates::kInputSpecs
    double lo = 0, hi = 0;
};

struct PlaneArrow {
    std::string label;     // e.g. "rho=+50%, mu_s=-10%"
    surrogates::Point to;  // the arrow's end (the base with the changes applied)
};

struct PlaneSpec {
    surrogates::Point base{};
    PlaneAxis x, y;
    int n = 41;  // grid points per axis
    std::vector<PlaneArrow> arrows;
    // Full runs; those whose five other inputs agree with the base within onPlaneTol (relative)
    // are compared with the model and drawn.
    std::optional<surrogates::Table> checks;
    double onPlaneTol = 0.01;
};

// Predicts M and its 95% interval on the n x n grid (points where mu_d <= mu_s or an input is not
// physical are left out), at each arrow's ends (with the interval of the difference from the two
// predictions' joint distribution), and at the check runs on the plane; writes plane.md, plane.csv
// and plane.png to dir (each to a temporary name, then renamed). Throws InputError for an axis
// range that is empty, the same input on both axes, a base or arrow point that is not physical,
// or n outside 5..201.
nlohmann::json inputPlane(const surrogates::Surrogate& model, const std::string& modelPath, const PlaneSpec& spec,
                          const std::filesystem::path& dir);

}  // namespace mixload::experiments
