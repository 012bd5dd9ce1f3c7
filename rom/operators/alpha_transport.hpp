// SPDX-License-Identifier: GPL-3.0-or-later
// The powder fraction carried by a face flux on the full mesh, explicitly: what a reduced model
// does with alpha when it keeps alpha on the mesh and reduces only the flow. As interFoam's alpha
// equation with the case's schemes: van Leer face values for div(phi,alpha) (alpha_f = alpha_U +
// psi(r) (alpha_linear - alpha_U)), plus the interface compression flux
// cAlpha |phi/|Sf|| (nHat_f . Sf) alpha_f (1 - alpha)_f (linear). Where MULES limits the
// compression iteratively, a single flux-corrected-transport pass (Zalesak) scales it face by face
// so that no cell leaves [0, 1]; without compression a front spreads over many cells and the
// runout, read where half a cell of powder remains, comes out far too long.
#pragma once

#include "rom/operators/fv_mesh.hpp"

namespace mixload::rom {

// The powder fraction clipped into [0, 1], as the densities and the viscosity mixture read it.
inline Eigen::VectorXd clampFraction(const Eigen::VectorXd& a) { return a.cwiseMax(0.0).cwiseMin(1.0); }

// Boundary values: outflow faces carry their cell's value, inflow faces `inflow` (air enters: 0).
Eigen::VectorXd alphaBoundary(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux, double inflow);

// One explicit step of length dt: alpha after it. cAlpha 0 leaves out the compression.
Eigen::VectorXd advanceAlpha(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux, double dt,
                             double inflow, double cAlpha);

// The largest step for which no cell sends out more than `courant` of its volume.
double transportStep(const FvMesh& m, const Eigen::VectorXd& flux, double courant);

}  // namespace mixload::rom
