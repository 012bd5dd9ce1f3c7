// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/operators/alpha_transport.hpp"

#include <cmath>
#include <limits>

#include "rom/operators/fv_operators.hpp"

namespace mixload::rom {

Eigen::VectorXd patchValues(const FvMesh& m, const std::map<std::string, double>& byPatch) {
    Eigen::VectorXd v = Eigen::VectorXd::Zero(m.boundaryFaces);
    for (const auto& [name, value] : byPatch) {
        const auto& p = m.patch(name);
        v.segment(p.start - m.internalFaces, p.size).setConstant(value);
    }
    return v;
}

Eigen::VectorXd alphaBoundary(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux,
                              const Eigen::VectorXd& inflow) {
    Eigen::VectorXd b(m.boundaryFaces);
    for (Eigen::Index i = 0; i < m.boundaryFaces; ++i) {
        const Eigen::Index f = m.internalFaces + i;
        b[i] = flux[f] < 0 ? inflow[i] : alpha[m.owner[f]];
    }
    return b;
}

Eigen::VectorXd advanceAlpha(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux, double dt,
                             const Eigen::VectorXd& inflow, double cAlpha) {
    const Eigen::VectorXd ab = alphaBoundary(m, alpha, flux, inflow);
    const Vectors g = grad(m, alpha, ab);
    // The bounded part: van Leer face values.
    Eigen::VectorXd af(m.faces());
    for (Eigen::Index i = 0; i < m.internalFaces; ++i) {
        const auto o = m.owner[i], n = m.neighbour[i];
        const auto up = flux[i] >= 0 ? o : n;
        // NVDTVD::r as OpenFOAM: the upwind cell's gradient against the jump across the face.
        const double jump = alpha[n] - alpha[o];
        const double along = (m.C.row(n) - m.C.row(o)).dot(g.row(up));
        const double r = std::abs(along) >= 1000 * std::abs(jump)
                             ? 2 * 1000 * std::copysign(1.0, along) * std::copysign(1.0, jump) - 1
                             : 2 * along / jump - 1;
        const double psi = (r + std::abs(r)) / (1 + std::abs(r));
        const double lin = m.weights[i] * alpha[o] + (1 - m.weights[i]) * alpha[n];
        af[i] = alpha[up] + psi * (lin - alpha[up]);
    }
    af.tail(m.boundaryFaces) = ab;
    Eigen::VectorXd low = alpha - dt * div(m, flux.cwiseProduct(af));
    if (cAlpha <= 0) return low;

    // The compression flux on internal faces, along the interface normal.
    const double deltaN = 1e-8 / std::cbrt(m.V.mean());
    Eigen::VectorXd comp = Eigen::VectorXd::Zero(m.internalFaces);
    double phicMax = 0;
    for (Eigen::Index i = 0; i < m.internalFaces; ++i) phicMax = std::max(phicMax, std::abs(flux[i]) / m.magSf[i]);
    for (Eigen::Index i = 0; i < m.internalFaces; ++i) {
        const auto o = m.owner[i], n = m.neighbour[i];
        const double w = m.weights[i];
        const Eigen::RowVector3d gf = w * g.row(o) + (1 - w) * g.row(n);
        const double nHat = gf.dot(m.Sf.row(i)) / (gf.norm() + deltaN);
        const double phir = std::min(cAlpha * std::abs(flux[i]) / m.magSf[i], phicMax) * nHat;
        const double a1 = w * alpha[o] + (1 - w) * alpha[n];
        comp[i] = phir * a1 * (1 - a1);
    }
    // Zalesak's limiter with the bounds 0 and 1: each cell takes in at most what fills it and gives
    // at most what it holds after the bounded step.
    Eigen::VectorXd in = Eigen::VectorXd::Zero(m.cells), out = Eigen::VectorXd::Zero(m.cells);
    for (Eigen::Index i = 0; i < m.internalFaces; ++i) {
        const double a = dt * comp[i];  // volume moved from owner to neighbour
        const auto from = a > 0 ? m.owner[i] : m.neighbour[i], to = a > 0 ? m.neighbour[i] : m.owner[i];
        out[from] += std::abs(a);
        in[to] += std::abs(a);
    }
    Eigen::VectorXd rIn(m.cells), rOut(m.cells);
    for (Eigen::Index c = 0; c < m.cells; ++c) {
        const double room = std::max(0.0, 1 - low[c]) * m.V[c], held = std::max(0.0, low[c]) * m.V[c];
        rIn[c] = in[c] > room ? room / in[c] : 1;
        rOut[c] = out[c] > held ? held / out[c] : 1;
    }
    Eigen::VectorXd limited(m.faces());
    limited.setZero();
    for (Eigen::Index i = 0; i < m.internalFaces; ++i) {
        const auto o = m.owner[i], n = m.neighbour[i];
        limited[i] = comp[i] * (comp[i] > 0 ? std::min(rOut[o], rIn[n]) : std::min(rIn[o], rOut[n]));
    }
    return low - dt * div(m, limited);
}

double transportStep(const FvMesh& m, const Eigen::VectorXd& flux, double courant) {
    Eigen::VectorXd out = Eigen::VectorXd::Zero(m.cells);
    for (Eigen::Index i = 0; i < m.faces(); ++i) {
        if (flux[i] > 0) out[m.owner[i]] += flux[i];
        else if (i < m.internalFaces) out[m.neighbour[i]] -= flux[i];
    }
    double dt = std::numeric_limits<double>::infinity();
    for (Eigen::Index c = 0; c < m.cells; ++c)
        if (out[c] > 0) dt = std::min(dt, courant * m.V[c] / out[c]);
    return dt;
}

}  // namespace mixload::rom
