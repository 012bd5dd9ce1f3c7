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
// Either way a flow evaluation needs the law at the points only.
//
// The convection, -rho (U.grad)U, is a sum over cells too: cell c's share of its projection is
// -rho_c P_c conv_c(a), with conv_c = (1/V_c) sum_{f of c} +-phi_f(a) U_f(a) quadratic in a and
// P_c (K x 3) how the face projection spreads cell c's acceleration onto the modes. ECSW keeps a few
// cells with positive weights; each needs only its own faces' flux and face velocity per mode.
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
    // d strainRate / d a at the points (P x K).
    Eigen::MatrixXd strainRateJacobian(const Eigen::VectorXd& a, const Eigen::VectorXd& strainRate) const;
    // The projected viscous term from mu at the points.
    Eigen::VectorXd projected(const Eigen::VectorXd& muAtPoints, const Eigen::VectorXd& a) const;
    // Its derivative in a, given d mu / d a at the points (P x K).
    Eigen::MatrixXd jacobian(const Eigen::VectorXd& muAtPoints, const Eigen::MatrixXd& dMuDa, const Eigen::VectorXd& a) const;
};

struct ConvectionHyper {
    std::vector<Eigen::Index> cells;     // the kept cells
    std::vector<Eigen::Index> faceStart; // cell e's faces are rows faceStart[e] .. faceStart[e + 1] - 1 below
    Eigen::MatrixXd faceFlux;            // F x K: +-|Sf| Psi_f (+ where the cell owns the face)
    Eigen::MatrixXd faceVelocity;        // 3 F x K: the face velocity of each mode (rows 3 f .. 3 f + 2)
    Eigen::MatrixXd project;             // K x 3 E: w_e P_e / V_e
    double trainingError = 0;

    int size() const { return static_cast<int>(cells.size()); }
    // The projected convection for the cell densities rho (on the whole mesh; read at the kept cells).
    Eigen::VectorXd projected(const Eigen::VectorXd& rho, const Eigen::VectorXd& a) const;
    // Its derivative in a (K x K): the convection is quadratic in a.
    Eigen::MatrixXd jacobian(const Eigen::VectorXd& rho, const Eigen::VectorXd& a) const;
};

struct HyperTraining {
    Eigen::MatrixXd mu;     // cells x N: the mixture viscosity of each training snapshot, as the model evaluates it
    Eigen::MatrixXd rho;    // cells x N: its density
    Eigen::MatrixXd flow;   // K x N: the snapshot's flow coefficients
};

// DEIM with `points` modes of mu, or ECSW stopped at `tolerance` (RMS relative error of F over the
// training snapshots) or `points` cells, whichever comes first.
ViscousHyper buildViscousHyper(const CollapseFlow& flow, const HyperTraining& training, HyperMethod method, int points,
                               double tolerance);
// ECSW of the convection on the same snapshots.
ConvectionHyper buildConvectionHyper(const CollapseFlow& flow, const HyperTraining& training, int points, double tolerance);

}  // namespace mixload::rom
