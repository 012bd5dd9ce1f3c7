// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/alpha_transport.hpp"

#include <cmath>
#include <limits>

#include "rom/fv_operators.hpp"

namespace mixload::rom {

Eigen::VectorXd alphaBoundary(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux, double inflow) {
    Eigen::VectorXd b(m.boundaryFaces);
    for (Eigen::Index i = 0; i < m.boundaryFaces; ++i) {
        const Eigen::Index f = m.internalFaces + i;
        b[i] = flux[f] < 0 ? inflow : alpha[m.owner[f]];
    }
    return b;
}

Eigen::VectorXd alphaRate(const FvMesh& m, const Eigen::VectorXd& alpha, const Eigen::VectorXd& flux, double inflow) {
    const Eigen::VectorXd ab = alphaBoundary(m, alpha, flux, inflow);
    const Vectors g = grad(m, alpha, ab);
    Eigen::VectorXd af(m.faces());
    for (Eigen::Index i = 0; i < m.internalFaces; ++i) {
        const auto o = m.owner[i], n = m.neighbour[i];
        const bool fromOwner = flux[i] >= 0;
        const auto up = fromOwner ? o : n;
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
    return -div(m, flux.cwiseProduct(af));
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
