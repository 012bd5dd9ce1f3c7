// SPDX-License-Identifier: GPL-3.0-or-later
// Explicit finite-volume operators on an FvMesh, the discrete operators of OpenFOAM's fvc with the
// schemes mixload's cases use (linear interpolation, Gauss linear gradient, Gauss linear corrected
// Laplacian): the building blocks of the reduced models' projected equations. Boundary values are
// given per non-empty boundary face (as snapshot files store them); for the Laplacian the boundary
// normal gradient is deltaCoeff (phi_b - phi_P), which is what fixedValue, zeroGradient, calculated
// and inletOutlet patches give. Verified against OpenFOAM's own fvc on real runs
// (tests/cfd/test_fv_operators.cpp).
#pragma once

#include <array>
#include <Eigen/Dense>

#include "rom/operators/fv_mesh.hpp"

namespace mixload::rom {

// Face values: internal faces by linear interpolation, boundary faces as given.
Eigen::VectorXd interpolate(const FvMesh& m, const Eigen::VectorXd& cells, const Eigen::VectorXd& boundary);
// Gauss linear gradient of a scalar: (1/V) sum_f Sf phi_f.
Vectors grad(const FvMesh& m, const Eigen::VectorXd& cells, const Eigen::VectorXd& boundary);
// Divergence of a face flux (internal then boundary faces): (1/V) sum_f +-flux_f.
Eigen::VectorXd div(const FvMesh& m, const Eigen::VectorXd& faceFlux);
// Gauss linear corrected Laplacian of a scalar (unit diffusivity).
Eigen::VectorXd laplacian(const FvMesh& m, const Eigen::VectorXd& cells, const Eigen::VectorXd& boundary);
// The same with a diffusivity given on every face (internal then boundary): fvc::laplacian(gamma_f, .).
Eigen::VectorXd laplacian(const FvMesh& m, const Eigen::VectorXd& faceGamma, const Eigen::VectorXd& cells,
                          const Eigen::VectorXd& boundary);
// Gauss linear gradient of each component of a vector field: g[j].row(c) is grad U_j in cell c,
// so OpenFOAM's grad(U)(i, j) = dU_j/dx_i = g[j](c, i).
std::array<Vectors, 3> gradComponents(const FvMesh& m, const Vectors& U, const Vectors& boundaryU);
// fvc::reconstruct: cell vectors from a face flux, (sum_f Sf Sf/|Sf|)^-1 sum_f Sf flux_f/|Sf|. A
// direction no face spans (the empty direction of a 2D mesh) gets 0, as OpenFOAM's inv does.
Vectors reconstruct(const FvMesh& m, const Eigen::VectorXd& faceFlux);
// The mu(I) shear rate sqrt(2) |sym(grad U)| from the Gauss linear gradient of U (cells x 3 and
// boundary faces x 3, row-major as snapshots store them).
Eigen::VectorXd strainRate(const FvMesh& m, const Vectors& U, const Vectors& boundaryU);
// The same from the gradient's components (gradComponents).
Eigen::VectorXd strainRate(const std::array<Vectors, 3>& gradU);
// The same for one cell's grad(U) (t(i, j) = dU_j/dx_i).
double strainRate(const Eigen::Matrix3d& t);

}  // namespace mixload::rom
