// SPDX-License-Identifier: GPL-3.0-or-later
// How well DEIM reproduces the mu(I) viscosity of stored runs: the viscosity of every snapshot is
// evaluated from its U and p (rom/operators/fv_operators, rom/operators/granular_viscosity), training snapshots give
// a POD basis and DEIM points, and every snapshot is reconstructed from its values at those cells.
// Training on every other stored time leaves the rest as a hold-out. This is the hyper-reduced
// term's own error, measured before any reduced model runs on it.
#pragma once
#include <nlohmann/json.hpp>

#include "store/snapshot_file.hpp"

namespace mixload::rom {

struct ViscosityDeimOptions {
    int modes = 10;         // DEIM points = POD modes of the viscosity
    bool logSpace = false;  // interpolate log(nu): the viscosity spans decades (the cap against fast shear)
};

// Per mode count up to options.modes: training and hold-out errors (volume-weighted relative L2 of
// nu, mean and max over snapshots), the cells picked, the snapshot counts.
nlohmann::json viscosityDeim(const store::SnapshotSet& set, const ViscosityDeimOptions& options);

}  // namespace mixload::rom
