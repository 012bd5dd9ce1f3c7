// SPDX-License-Identifier: GPL-3.0-or-later
// The reduced flow equations of the POD-Galerkin collapse (rom/galerkin/collapse_galerkin): for a powder
// fraction held fixed over a step, the densities, the reduced mass matrix and gravity term
// (Frozen), and for flow coefficients a, the projected convection and viscous stress (faceForce),
// the rate da/dt, and the pressure the reduced momentum implies. The derivation is in
// collapse_galerkin.hpp.
#pragma once

#include <array>

#include <Eigen/Dense>
#include <Eigen/Sparse>

#include "rom/galerkin/collapse_galerkin.hpp"

namespace mixload::rom {

// What the flow equations hold fixed over one step: the densities, viscosity mixture inputs, the
// lithostatic pressure, the reduced mass matrix and gravity term, all from alpha.
struct Frozen {
    Eigen::VectorXd alpha, rhoC, rhoF, p, gravityFaces, gravityTerm;
    Eigen::VectorXd alphaAtPoints, pAtPoints;  // at the DEIM points of a hyper-reduced model
    Eigen::MatrixXd mass;
    Eigen::VectorXd massRhoF;  // the face densities mass was assembled with (within a round-off tolerance of rhoF)
    Eigen::LLT<Eigen::MatrixXd> massLlt;
};

class CollapseFlow {
  public:
    explicit CollapseFlow(const CollapseGalerkin& r);

    // With `previous`, the reduced mass matrix is updated on the faces whose density changed since
    // (the interface's band) instead of assembled over every face: the same matrix to round-off.
    Frozen freeze(const Eigen::VectorXd& alphaIn, const Frozen* previous = nullptr) const;
    // Replaces the frozen (lithostatic) pressure, at the hyper-reduction's points too.
    void setPressure(Frozen& z, Eigen::VectorXd p) const;

    // The total pressure the reduced flow implies: per face, the momentum the projection left
    // unbalanced, rho_f V_f dv_f/dt - V_f F_f - gravity_f, is the pressure's -|Sf| (p_N - p_O);
    // its gradient part, found by least squares (a Poisson equation), is p_rgh, and p = p_rgh + rho gh.
    Eigen::VectorXd recoverPressure(const Frozen& z, const Eigen::VectorXd& a) const;

    Vectors cellVelocity(const Eigen::VectorXd& a) const { return asVectors(r_.cellU * a); }

    Vectors boundaryVelocity(const Vectors& U) const;

    // M da/dt = the projected convection, viscous and gravity terms.
    Eigen::VectorXd rate(const Frozen& z, const Eigen::VectorXd& a) const;
    // d rate / d a, for a model with both terms hyper-reduced (hasJacobian); else the integrator
    // takes difference quotients of rate.
    bool hasJacobian() const { return r_.hyper && r_.convectionHyper; }
    Eigen::MatrixXd rateJacobian(const Frozen& z, const Eigen::VectorXd& a) const;
    // Psi^T faceForce, with the viscous term hyper-reduced when the model has its DEIM.
    Eigen::VectorXd projectedForce(const Frozen& z, const Eigen::VectorXd& a) const;

    // Per face: V_f n_f . interp(-rho (U.grad)U + div(mu (grad U + dev2 grad U^T))), on the whole mesh.
    Eigen::VectorXd faceForce(const Frozen& z, const Eigen::VectorXd& a) const;
    // Its parts, per cell: -rho (U.grad)U, and the viscous term for a mixture viscosity mu (G: grad U).
    Vectors convection(const Frozen& z, const Eigen::VectorXd& a, const Vectors& U, const Vectors& Ub) const;
    Vectors viscous(const Eigen::VectorXd& mu, const Vectors& U, const Vectors& Ub, const std::array<Vectors, 3>& G) const;
    // Per face: V_f n_f . interp(A)_f.
    Eigen::VectorXd faceProject(const Vectors& A) const;

    // The mixture viscosity alpha rho nu + (1 - alpha) rho_air nu_air from the powder's nu.
    Eigen::VectorXd mixtureViscosity(const Eigen::VectorXd& alpha, const Eigen::VectorXd& nuPowder) const;
    // The model's mixture viscosity on the whole mesh, and at the DEIM points (hyper-reduced model).
    Eigen::VectorXd viscosity(const Frozen& z, const Eigen::VectorXd& a) const;
    Eigen::VectorXd hyperViscosity(const Frozen& z, const Eigen::VectorXd& a) const;

    const CollapseGalerkin& model() const { return r_; }

    Eigen::VectorXd flux(const Eigen::VectorXd& a) const { return m_.magSf.cwiseProduct(r_.flow.modes * a); }

    // Coefficients of a flux in the density-weighted product at alpha.
    Eigen::VectorXd project(const Frozen& z, const Eigen::VectorXd& phi) const;

    double potentialEnergy(const Eigen::VectorXd& alpha) const;


  private:
    const CollapseGalerkin& r_;
    const FvMesh& m_;
    ColumnPressure pressure_;
    Eigen::VectorXd Vf_, ghf_;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> poisson_;
};

// Owner values on the boundary faces (zero gradient).
Eigen::VectorXd ownerValues(const FvMesh& m, const Eigen::VectorXd& cells);

}  // namespace mixload::rom
