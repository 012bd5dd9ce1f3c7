// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/operators/steady_transport.hpp"

#include <Eigen/Sparse>

#include "common/input_error.hpp"
#include "rom/operators/alpha_transport.hpp"

namespace mixload::rom {

namespace {
using Triplets = std::vector<Eigen::Triplet<double>>;
}  // namespace

SteadyPowder steadyPowder(const FvMesh& m, const Eigen::VectorXd& flux, const std::map<std::string, double>& inflowFraction) {
    const Eigen::Index n = m.cells;
    const Eigen::VectorXd boundaryFraction = patchValues(m, inflowFraction);
    double inflow = 0;
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
    Triplets t;
    t.reserve(static_cast<size_t>(2 * m.internalFaces + n + m.boundaryFaces));
    for (Eigen::Index f = 0; f < m.internalFaces; ++f) {
        const auto o = m.owner[f], nb = m.neighbour[f];
        const double F = flux[f];
        if (F >= 0) {
            t.emplace_back(o, o, F);
            t.emplace_back(nb, o, -F);
        } else {
            t.emplace_back(o, nb, F);
            t.emplace_back(nb, nb, -F);
        }
    }
    for (Eigen::Index i = 0; i < m.boundaryFaces; ++i) {
        const Eigen::Index f = m.internalFaces + i;
        const double F = flux[f];
        if (F >= 0) {
            t.emplace_back(m.owner[f], m.owner[f], F);
        } else {
            rhs[m.owner[f]] -= F * boundaryFraction[i];
            inflow -= F * boundaryFraction[i];
        }
    }
    if (!(inflow > 0)) throw InputError("flux", "no powder inflow", "a flux entering through a patch that brings powder");
    const double dtau = kSteadyFillTimes * m.V.sum() / inflow;
    for (Eigen::Index c = 0; c < n; ++c) t.emplace_back(c, c, m.V[c] / dtau);
    Eigen::SparseMatrix<double> A(n, n);
    A.setFromTriplets(t.begin(), t.end());
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(A);
    if (lu.info() != Eigen::Success) throw std::runtime_error("steady powder transport: the upwind matrix is singular");
    SteadyPowder out;
    out.alpha = lu.solve(rhs);
    out.residual = (A * out.alpha - rhs).norm() / rhs.norm();
    out.inflow = inflow;
    for (Eigen::Index i = 0; i < m.boundaryFaces; ++i) {
        const Eigen::Index f = m.internalFaces + i;
        if (flux[f] > 0) out.outflow += flux[f] * out.alpha[m.owner[f]];
    }
    return out;
}

Eigen::VectorXd fluxFromVelocity(const FvMesh& m, const Vectors& U, const Vectors& boundaryU,
                                 const std::vector<store::CaseFile::MrfZone>& zones, const std::string& openPatch) {
    const Eigen::Index n = m.cells;
    // The rotor's velocity at each face of a zone cell (zero elsewhere).
    std::vector<const store::CaseFile::MrfZone*> zoneOf(static_cast<size_t>(n), nullptr);
    for (const auto& z : zones)
        for (const auto c : z.cells) zoneOf.at(static_cast<size_t>(c)) = &z;
    const auto frame = [&](Eigen::Index f, const store::CaseFile::MrfZone* z) {
        if (!z) return 0.0;
        const Eigen::Vector3d r = m.Cf.row(f).transpose() - z->origin;
        return (z->omega * z->axis).cross(r).dot(m.Sf.row(f).transpose());
    };
    Eigen::VectorXd flux(m.faces());
    for (Eigen::Index f = 0; f < m.internalFaces; ++f) {
        const auto o = m.owner[f], nb = m.neighbour[f];
        const Eigen::RowVector3d uf = m.weights[f] * U.row(o) + (1 - m.weights[f]) * U.row(nb);
        const auto* z = zoneOf[static_cast<size_t>(o)] ? zoneOf[static_cast<size_t>(o)] : zoneOf[static_cast<size_t>(nb)];
        flux[f] = uf.dot(m.Sf.row(f)) - frame(f, z);
    }
    // Nothing crosses a wall, turning or not: MRF sets the flux of its rotating walls to zero.
    for (const auto& p : m.patches)
        for (Eigen::Index f = p.start; f < p.start + p.size; ++f)
            flux[f] = p.type == "wall" ? 0.0
                                       : boundaryU.row(f - m.internalFaces).dot(m.Sf.row(f)) -
                                             frame(f, zoneOf[static_cast<size_t>(m.owner[f])]);

    // div(flux - k grad_f phi) = 0 with phi = 0 on the open patch: L phi = -div(flux), where L is
    // the orthogonal Laplacian's negative (k = |Sf| deltaCoeff on each face).
    const auto& open = m.patch(openPatch);
    Triplets t;
    Eigen::VectorXd b = Eigen::VectorXd::Zero(n);
    for (Eigen::Index f = 0; f < m.internalFaces; ++f) {
        const double k = m.magSf[f] * m.deltaCoeffs[f];
        const auto o = m.owner[f], nb = m.neighbour[f];
        t.emplace_back(o, o, k);
        t.emplace_back(nb, nb, k);
        t.emplace_back(o, nb, -k);
        t.emplace_back(nb, o, -k);
        b[o] -= flux[f];
        b[nb] += flux[f];
    }
    for (Eigen::Index f = m.internalFaces; f < m.faces(); ++f) b[m.owner[f]] -= flux[f];
    for (Eigen::Index f = open.start; f < open.start + open.size; ++f)
        t.emplace_back(m.owner[f], m.owner[f], m.magSf[f] * m.deltaCoeffs[f]);
    Eigen::SparseMatrix<double> L(n, n);
    L.setFromTriplets(t.begin(), t.end());
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(L);
    if (ldlt.info() != Eigen::Success) throw std::runtime_error("flux projection: the Laplacian is singular");
    const Eigen::VectorXd phi = ldlt.solve(b);
    for (Eigen::Index f = 0; f < m.internalFaces; ++f)
        flux[f] -= m.magSf[f] * m.deltaCoeffs[f] * (phi[m.neighbour[f]] - phi[m.owner[f]]);
    for (Eigen::Index f = open.start; f < open.start + open.size; ++f) flux[f] += m.magSf[f] * m.deltaCoeffs[f] * phi[m.owner[f]];
    return flux;
}

}  // namespace mixload::rom
