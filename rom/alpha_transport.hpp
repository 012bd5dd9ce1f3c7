// SPDX-License-Identifier: GPL-3.0-or-later
// The powder fraction carried by a face flux on the full mesh, explicitly: what a reduced model
// does with alpha when it keeps alpha on the mesh and reduces only the flow. Face values are van
// Leer limited (OpenFOAM's "Gauss vanLeer" for div(phi,alpha): alpha_f = alpha_U + psi(r)
// (alpha_linear - alpha_U)), which keeps alpha within [0, 1] for steps below half the Courant limit.
// There is no interface compression, so fronts spread more than in interFoam's MULES.
#pragma once

#include "rom/fv_mesh.hpp"

namespace mixload::rom {

// Boundary values: outflow faces carry their cell's value, inflow faces `inflow` (air enters: 0).
Eigen::VectorXd alphaBoundary(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux, double inflow);

// d alpha/dt = -div(flux alpha_f): the rate of change, per cell.
Eigen::VectorXd alphaRate(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux, double inflow);

// The largest step for which no cell sends out more than `courant` of its volume.
double transportStep(const FvMesh& m, const Eigen::VectorXd& flux, double courant);

}  // namespace mixload::rom
