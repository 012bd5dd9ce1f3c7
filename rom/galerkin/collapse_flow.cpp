// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/galerkin/collapse_flow.hpp"

#include <algorithm>
#include <cmath>

#include "rom/operators/alpha_transport.hpp"
#include "rom/operators/fv_operators.hpp"

namespace mixload::rom {

// Owner values on the boundary faces (zero gradient).
Eigen::VectorXd ownerValues(const FvMesh& m, const Eigen::VectorXd& cells) {
    Eigen::VectorXd b(m.boundaryFaces);
    for (Eigen::Index i = 0; i < m.boundaryFaces; ++i) b[i] = cells[m.owner[m.internalFaces + i]];
    return b;
}

CollapseFlow::CollapseFlow(const CollapseGalerkin& r)
    : r_(r), m_(r.mesh), pressure_(r.mesh, r.gravity), Vf_(m_.magSf.cwiseQuotient(m_.deltaCoeffs)),
      ghf_(-r.gravity * m_.Cf.col(1)) {
    // The pressure recovery's normal equations: the face-difference operator weighted by
    // |Sf| deltaCoeff (the FV Laplacian), p_rgh = 0 on the open faces; constant, factored once.
    std::vector<Eigen::Triplet<double>> t;
    for (Eigen::Index f = 0; f < m_.faces(); ++f) {
        const double w = m_.magSf[f] * m_.deltaCoeffs[f];
        const auto o = m_.owner[f];
        if (f < m_.internalFaces) {
            const auto n = m_.neighbour[f];
            t.emplace_back(o, o, w);
            t.emplace_back(n, n, w);
            t.emplace_back(o, n, -w);
            t.emplace_back(n, o, -w);
        } else if (r_.walls[static_cast<size_t>(f - m_.internalFaces)] == CollapseGalerkin::Wall::open) {
            t.emplace_back(o, o, w);
        }
    }
    Eigen::SparseMatrix<double> L(m_.cells, m_.cells);
    L.setFromTriplets(t.begin(), t.end());
    poisson_.compute(L);
    if (poisson_.info() != Eigen::Success) throw std::runtime_error("pressure recovery: the Laplacian is singular");
}

Frozen CollapseFlow::freeze(const Eigen::VectorXd& alphaIn, const Frozen* previous) const {
    Frozen z;
    z.alpha = clampFraction(alphaIn);
    const double rho1 = r_.law.rho, rho2 = r_.airRho;
    z.rhoC = (rho2 + (rho1 - rho2) * z.alpha.array()).matrix();
    z.rhoF = interpolate(m_, z.rhoC, ownerValues(m_, z.rhoC));
    z.p = pressure_(z.rhoC);
    const Eigen::MatrixXd& Psi = r_.flow.modes;
    if (previous && previous->massRhoF.size() == z.rhoF.size()) {
        // Rank-one updates on the faces whose density moved by more than round-off since the matrix
        // was assembled; the rest keep their assembled density, so no error accumulates.
        z.mass = previous->mass;
        z.massRhoF = previous->massRhoF;
        const double tiny = 1e-12 * std::max(rho1, rho2);
        for (Eigen::Index f = 0; f < m_.faces(); ++f) {
            const double d = z.rhoF[f] - z.massRhoF[f];
            if (std::abs(d) <= tiny) continue;
            z.mass.noalias() += (Vf_[f] * d) * Psi.row(f).transpose() * Psi.row(f);
            z.massRhoF[f] = z.rhoF[f];
        }
    } else {
        z.mass = Psi.transpose() * (Vf_.cwiseProduct(z.rhoF).asDiagonal() * Psi);
        z.massRhoF = z.rhoF;
    }
    z.massLlt.compute(z.mass);
    z.gravityFaces = Eigen::VectorXd::Zero(m_.faces());
    for (Eigen::Index i = 0; i < m_.internalFaces; ++i)
        z.gravityFaces[i] = -m_.magSf[i] * ghf_[i] * (z.rhoC[m_.neighbour[i]] - z.rhoC[m_.owner[i]]);
    z.gravityTerm = Psi.transpose() * z.gravityFaces;
    if (r_.hyper) {
        const auto& pts = r_.hyper->points;
        z.alphaAtPoints.resize(static_cast<Eigen::Index>(pts.size()));
        for (size_t i = 0; i < pts.size(); ++i) z.alphaAtPoints[static_cast<Eigen::Index>(i)] = z.alpha[pts[i]];
    }
    setPressure(z, std::move(z.p));
    return z;
}

void CollapseFlow::setPressure(Frozen& z, Eigen::VectorXd p) const {
    z.p = std::move(p);
    if (!r_.hyper) return;
    const auto& pts = r_.hyper->points;
    z.pAtPoints.resize(static_cast<Eigen::Index>(pts.size()));
    for (size_t i = 0; i < pts.size(); ++i) z.pAtPoints[static_cast<Eigen::Index>(i)] = z.p[pts[i]];
}

Eigen::VectorXd CollapseFlow::recoverPressure(const Frozen& z, const Eigen::VectorXd& a) const {
    const Eigen::VectorXd force = faceForce(z, a);
    const Eigen::VectorXd dadt = z.massLlt.solve(r_.flow.modes.transpose() * force + z.gravityTerm);
    const Eigen::VectorXd residual =
        Vf_.cwiseProduct(z.rhoF).cwiseProduct(r_.flow.modes * dadt) - force - z.gravityFaces;
    Eigen::VectorXd b = Eigen::VectorXd::Zero(m_.cells);
    for (Eigen::Index f = 0; f < m_.faces(); ++f) {
        const bool internal = f < m_.internalFaces;
        if (!internal && r_.walls[static_cast<size_t>(f - m_.internalFaces)] != CollapseGalerkin::Wall::open) continue;
        const double jump = -residual[f] / m_.magSf[f];  // p_N - p_O (p_b - p_O on an open face, p_b = 0)
        const double w = m_.magSf[f] * m_.deltaCoeffs[f];
        b[m_.owner[f]] -= w * jump;
        if (internal) b[m_.neighbour[f]] += w * jump;
    }
    const Eigen::VectorXd prgh = poisson_.solve(b);
    return prgh + z.rhoC.cwiseProduct(-r_.gravity * m_.C.col(1));
}

Vectors CollapseFlow::boundaryVelocity(const Vectors& U) const {
    Vectors b(m_.boundaryFaces, 3);
    for (Eigen::Index i = 0; i < m_.boundaryFaces; ++i) {
        const Eigen::Index f = m_.internalFaces + i;
        const Eigen::RowVector3d up = U.row(m_.owner[f]);
        switch (r_.walls[static_cast<size_t>(i)]) {
            case CollapseGalerkin::Wall::noSlip: b.row(i).setZero(); break;
            case CollapseGalerkin::Wall::slip: {
                const Eigen::RowVector3d n = m_.Sf.row(f) / m_.magSf[f];
                b.row(i) = up - up.dot(n) * n;
                break;
            }
            case CollapseGalerkin::Wall::open: b.row(i) = up; break;
        }
    }
    return b;
}

Eigen::VectorXd CollapseFlow::rate(const Frozen& z, const Eigen::VectorXd& a) const {
    return z.massLlt.solve(projectedForce(z, a) + z.gravityTerm);
}

Eigen::MatrixXd CollapseFlow::rateJacobian(const Frozen& z, const Eigen::VectorXd& a) const {
    if (!hasJacobian()) throw std::logic_error("reduced collapse: a Jacobian needs both terms hyper-reduced");
    const ViscousHyper& h = *r_.hyper;
    const Eigen::VectorXd sr = h.strainRate(a);
    const Eigen::VectorXd mu = mixtureViscosity(z.alphaAtPoints, r_.law.nu(sr, z.pAtPoints));
    // The mixture viscosity's powder part alpha rho nu(gammaDot) is all that moves with a.
    const Eigen::VectorXd dMuDsr =
        (z.alphaAtPoints.array() * r_.law.rho * r_.law.dNuDStrainRate(sr, z.pAtPoints).array()).matrix();
    const Eigen::MatrixXd dMuDa = dMuDsr.asDiagonal() * h.strainRateJacobian(a, sr);
    return z.massLlt.solve(r_.convectionHyper->jacobian(z.rhoC, a) + h.jacobian(mu, dMuDa, a));
}

Eigen::VectorXd CollapseFlow::projectedForce(const Frozen& z, const Eigen::VectorXd& a) const {
    const Eigen::MatrixXd& Psi = r_.flow.modes;
    if (!r_.hyper) return Psi.transpose() * faceForce(z, a);
    const Eigen::VectorXd viscousTerm = r_.hyper->projected(hyperViscosity(z, a), a);
    if (r_.convectionHyper) return r_.convectionHyper->projected(z.rhoC, a) + viscousTerm;
    const Vectors U = cellVelocity(a);
    return Psi.transpose() * faceProject(convection(z, a, U, boundaryVelocity(U))) + viscousTerm;
}

Eigen::VectorXd CollapseFlow::mixtureViscosity(const Eigen::VectorXd& alpha, const Eigen::VectorXd& nuPowder) const {
    return (alpha.array() * r_.law.rho * nuPowder.array() + (1 - alpha.array()) * r_.airRho * r_.airNu).matrix();
}

Eigen::VectorXd CollapseFlow::viscosity(const Frozen& z, const Eigen::VectorXd& a) const {
    const Vectors U = cellVelocity(a);
    return mixtureViscosity(z.alpha, r_.law.nu(strainRate(m_, U, boundaryVelocity(U)), z.p));
}

Eigen::VectorXd CollapseFlow::hyperViscosity(const Frozen& z, const Eigen::VectorXd& a) const {
    return mixtureViscosity(z.alphaAtPoints, r_.law.nu(r_.hyper->strainRate(a), z.pAtPoints));
}

Vectors CollapseFlow::convection(const Frozen& z, const Eigen::VectorXd& a, const Vectors& U, const Vectors& Ub) const {
    const Eigen::VectorXd flux = m_.magSf.cwiseProduct(r_.flow.modes * a);
    Vectors A(m_.cells, 3);
    for (int j = 0; j < 3; ++j)
        A.col(j) = -z.rhoC.cwiseProduct(div(m_, flux.cwiseProduct(interpolate(m_, U.col(j), Ub.col(j)))));
    return A;
}

Vectors CollapseFlow::viscous(const Eigen::VectorXd& mu, const Vectors& U, const Vectors& Ub,
                              const std::array<Vectors, 3>& G) const {
    const Eigen::VectorXd muF = interpolate(m_, mu, ownerValues(m_, mu));
    // The explicit part of interFoam's divDevRhoReff: div(mu dev2(grad(U)^T)), the face vector
    // Sf . T_f with T linearly interpolated (owner value on boundary faces), in one pass.
    std::vector<Eigen::Matrix3d> T(static_cast<size_t>(m_.cells));
    for (Eigen::Index c = 0; c < m_.cells; ++c) {
        Eigen::Matrix3d g;  // g(i, j) = dU_j/dx_i, OpenFOAM's grad(U)
        for (int j = 0; j < 3; ++j) g.col(j) = G[static_cast<size_t>(j)].row(c).transpose();
        T[static_cast<size_t>(c)] = mu[c] * (g.transpose() - 2.0 / 3.0 * g.trace() * Eigen::Matrix3d::Identity());
    }
    std::array<Eigen::VectorXd, 3> tf;
    for (auto& v : tf) v.resize(m_.faces());
    for (Eigen::Index f = 0; f < m_.faces(); ++f) {
        const auto& To = T[static_cast<size_t>(m_.owner[f])];
        const Eigen::Matrix3d Tf = f < m_.internalFaces
                                       ? Eigen::Matrix3d(m_.weights[f] * To + (1 - m_.weights[f]) * T[static_cast<size_t>(m_.neighbour[f])])
                                       : To;
        const Eigen::RowVector3d st = m_.Sf.row(f) * Tf;
        for (int j = 0; j < 3; ++j) tf[static_cast<size_t>(j)][f] = st[j];
    }
    Vectors A(m_.cells, 3);
    for (int j = 0; j < 3; ++j) {
        const Eigen::VectorXd uj = U.col(j), ubj = Ub.col(j);
        A.col(j) = laplacian(m_, muF, uj, ubj) + div(m_, tf[j]);
    }
    return A;
}

Eigen::VectorXd CollapseFlow::faceProject(const Vectors& A) const {
    // n_f . interp(A)_f, weighted by the face volume.
    Eigen::VectorXd force(m_.faces());
    for (Eigen::Index f = 0; f < m_.faces(); ++f) {
        Eigen::RowVector3d af = A.row(m_.owner[f]);
        if (f < m_.internalFaces) af = m_.weights[f] * af + (1 - m_.weights[f]) * A.row(m_.neighbour[f]);
        force[f] = Vf_[f] * af.dot(m_.Sf.row(f)) / m_.magSf[f];
    }
    return force;
}

Eigen::VectorXd CollapseFlow::faceForce(const Frozen& z, const Eigen::VectorXd& a) const {
    const Vectors U = cellVelocity(a);
    const Vectors Ub = boundaryVelocity(U);
    const auto G = gradComponents(m_, U, Ub);
    const Eigen::VectorXd mu = mixtureViscosity(z.alpha, r_.law.nu(strainRate(G), z.p));
    return faceProject(convection(z, a, U, Ub) + viscous(mu, U, Ub, G));
}

Eigen::VectorXd CollapseFlow::project(const Frozen& z, const Eigen::VectorXd& phi) const {
    const Eigen::VectorXd v = phi.cwiseQuotient(m_.magSf);
    return z.massLlt.solve(r_.flow.modes.transpose() * Vf_.cwiseProduct(z.rhoF).cwiseProduct(v));
}

double CollapseFlow::potentialEnergy(const Eigen::VectorXd& alpha) const {
    const double y0 = m_.C.col(1).minCoeff();
    return r_.law.rho * r_.gravity * (alpha.cwiseProduct(m_.V).array() * (m_.C.col(1).array() - y0)).sum();
}

}  // namespace mixload::rom
