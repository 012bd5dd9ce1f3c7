// SPDX-License-Identifier: GPL-3.0-or-later
// Using a POD-Galerkin collapse model: against stored runs (a reproduction for the runs it was
// trained on, a prediction for the others) and at new mu(I) coefficients.
#pragma once

#include <nlohmann/json.hpp>

#include "rom/galerkin/collapse_galerkin.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::rom {

// Runs the model from rest at t = 0 (the initial column, no flow) with the law of a run's snapshot
// file (its mu_s, mu_d, I0, cap) through the run's stored times, and compares with every stored
// field: alpha and U relative errors beside their projection errors, the runout and height, the
// pressure (the model's and the lithostatic closure's on the stored fields), and the costs.
nlohmann::json checkCollapse(const CollapseGalerkin& rom, const store::SnapshotFile& run);

// Refuses (InputError naming the coefficient) mu(I) coefficients farther outside the training runs'
// range than a quarter of that range (at least 5% of the value, so that a one-run model still
// answers near its run): a reduced model is an interpolant, as the surrogates are.
void requireNearTraining(const CollapseGalerkin& rom, double muS, double muD, double i0);

// A prediction: the model from rest with these mu(I) coefficients (as the solver reads them) to
// endTstar, L*(t), H*(t) and the kinetic energy at `perTstar` times per t*, and L*f and H*f.
// trajectory, when given, receives the model's fields at those times.
nlohmann::json predictCollapse(const CollapseGalerkin& rom, double muS, double muD, double i0, double endTstar,
                               int perTstar, CollapseTrajectory* trajectory = nullptr);

}  // namespace mixload::rom
