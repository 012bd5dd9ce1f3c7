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
#include <map>
#include <string>

#include "rom/operators/fv_mesh.hpp"

namespace mixload::rom {

// The powder fraction clipped into [0, 1], as the densities and the viscosity mixture read it.
inline Eigen::VectorXd clampFraction(const Eigen::VectorXd& a) { return a.cwiseMax(0.0).cwiseMin(1.0); }

// Per boundary face, the value given for its patch (by name; a name that is not a patch is
// refused), 0 on the other patches: e.g. the powder fraction entering through an inlet.
Eigen::VectorXd patchValues(const FvMesh& m, const std::map<std::string, double>& byPatch);

// Boundary values: outflow faces carry their cell's value, inflow faces the given inflow value
// (per boundary face, or one for all: air enters with 0).
Eigen::VectorXd alphaBoundary(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux,
                              const Eigen::VectorXd& inflow);
inline Eigen::VectorXd alphaBoundary(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux, double inflow) {
    return alphaBoundary(m, alpha, flux, Eigen::VectorXd::Constant(m.boundaryFaces, inflow));
}

// One explicit step of length dt: alpha after it. cAlpha 0 leaves out the compression.
Eigen::VectorXd advanceAlpha(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux, double dt,
                             const Eigen::VectorXd& inflow, double cAlpha);
inline Eigen::VectorXd advanceAlpha(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux, double dt,
                                    double inflow, double cAlpha) {
    return advanceAlpha(m, alpha, flux, dt, Eigen::VectorXd::Constant(m.boundaryFaces, inflow), cAlpha);
}

// The largest step for which no cell sends out more than `courant` of its volume.
double transportStep(const FvMesh& m, const Eigen::VectorXd& flux, double courant);

}  // namespace mixload::rom
