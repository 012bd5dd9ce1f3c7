// SPDX-License-Identifier: GPL-3.0-or-later
// The reduced models' benchmark on the collapse (issue 15): full runs at training points and at
// held-out points (the reference), the POD-Galerkin model built on the training runs' snapshots, a POD
// regression of the final deposit (rom/regression/pod_regression) and a kriging model of L*f and H*f fitted to
// the same training runs, each predicting the held-out runs.
// Per method: the online time per answer, the error in L*f and H*f (and in the fields for the
// Galerkin model, beside the projection error that bounds it), the offline cost and the number of
// answers after which a method has paid for it. Everything runs in this one process; full runs
// resume from their run directories, so a stopped benchmark picks up where it was.
#pragma once

#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "rom/galerkin/collapse_galerkin.hpp"
#include "scene/collapse_overrides.hpp"

namespace mixload::experiments {

struct CollapsePoint {
    double muS = 0, muD = 0, i0 = 0;
};

struct RomBench {
    scene::CollapseOverrides base;  // material, aspect, cells; the points override mu_s, mu_d, I0
    std::vector<CollapsePoint> train, heldOut;
    // The full model itself on coarser meshes (cells per column length) at the held-out points: the
    // cheapest full answers, measured against the same reference.
    std::vector<int> coarseCells;
    rom::CollapseGalerkinOptions options;
    // A second Galerkin model with the mu(I) and convection terms hyper-reduced by ECSW to this
    // training error (0: none).
    double hyperTolerance = 0.003;
    std::filesystem::path out;
    bool progress = false;
};

// Writes <out>/table.md, table.csv, rom-bench.png, and the time-against-error summary pareto.md,
// pareto.csv and pareto.png (per method the median online time per answer and median |relative
// error| in L*f and H*f, offline cost apart, the Pareto front marked); returns the rows and costs.
nlohmann::json runRomBench(const RomBench& bench);

}  // namespace mixload::experiments
