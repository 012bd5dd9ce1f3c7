// SPDX-License-Identifier: GPL-3.0-or-later
// The mu(I) viscous term of the reduced collapse, hyper-reduced: evaluated from the viscosity at a
// few cells instead of the whole mesh.
//
// interFoam's viscous term, div(mu_f grad U) + div(mu dev2(grad U^T)), is linear in the mixture
// viscosity mu for a fixed velocity and linear in the velocity for a fixed mu. Its projection on
// the flow modes is therefore exactly
//   F(a) = sum_c mu_c(a) B_c a,   B_c[:, k] = Psi^T (face force of the viscous term with mu = 1 in
//                                               cell c and 0 elsewhere, U = U_k),
// with mu_c(a) the law at cell c (the shear rate from each mode's gradient there, the frozen powder
// fraction and pressure). Two ways to keep only a few cells, both with matrices computed once at build:
// - DEIM: mu ~ Theta c, c = (P^T Theta)^-1 mu(P), so F ~ sum_q c_q V_q a with V_q = sum_c Theta_qc B_c.
//   The interpolated mu can turn negative between the points, which makes the term anti-dissipative.
// - ECSW (energy-conserving sampling and weighting): F ~ sum_{e in E} w_e mu_e B_e a with positive
//   weights w_e found by non-negative least squares on the training snapshots, so each kept cell
//   contributes with the sign its full-mesh counterpart has.
// Either way a flow evaluation needs the law at the points only; the convection stays on the mesh.
#pragma once

#include <vector>

#include <Eigen/Dense>

namespace mixload::rom {

class CollapseFlow;

enum class HyperMethod { deim, ecsw };

struct ViscousHyper {
    HyperMethod method = HyperMethod::ecsw;
    std::vector<Eigen::Index> points;  // the cells where the law is evaluated
    Eigen::MatrixXd toCoefficients;    // P x P: (P^T Theta)^-1 (DEIM) or diag(w) (ECSW)
    Eigen::MatrixXd gradAtPoints;      // 9 P x K: grad(U)(i, j) of mode k at point p in row 9 p + 3 i + j
    Eigen::MatrixXd viscous;           // K K x P, column-major K x K blocks: V_q (DEIM) or B_e (ECSW)
    double trainingError = 0;          // RMS over training snapshots of |F~ - F| / |F|

    int size() const { return static_cast<int>(points.size()); }
    // sqrt(2) |sym grad U| at the points for flow coefficients a (the mesh's strainRate there).
    Eigen::VectorXd strainRate(const Eigen::VectorXd& a) const;
    // The projected viscous term from mu at the points.
    Eigen::VectorXd projected(const Eigen::VectorXd& muAtPoints, const Eigen::VectorXd& a) const;
};

struct HyperTraining {
    Eigen::MatrixXd mu;     // cells x N: the mixture viscosity of each training snapshot, as the model evaluates it
    Eigen::MatrixXd flow;   // K x N: the snapshot's flow coefficients
};

// DEIM with `points` modes of mu, or ECSW stopped at `tolerance` (RMS relative error of F over the
// training snapshots) or `points` cells, whichever comes first.
ViscousHyper buildViscousHyper(const CollapseFlow& flow, const HyperTraining& training, HyperMethod method, int points,
                               double tolerance);

}  // namespace mixload::rom
