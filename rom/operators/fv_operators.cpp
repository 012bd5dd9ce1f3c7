// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/operators/fv_operators.hpp"

#include <cmath>
#include <stdexcept>

namespace mixload::rom {

namespace {
void requireSizes(const FvMesh& m, Eigen::Index cells, Eigen::Index boundary) {
    if (cells != m.cells || boundary != m.boundaryFaces)
        throw std::invalid_argument("fv operator: " + std::to_string(cells) + " cell and " + std::to_string(boundary) +
                                    " boundary values for a mesh of " + std::to_string(m.cells) + " cells and " +
                                    std::to_string(m.boundaryFaces) + " boundary faces");
}
}  // namespace

Eigen::VectorXd interpolate(const FvMesh& m, const Eigen::VectorXd& cells, const Eigen::VectorXd& boundary) {
    requireSizes(m, cells.size(), boundary.size());
    Eigen::VectorXd f(m.faces());
    for (Eigen::Index i = 0; i < m.internalFaces; ++i) {
        const double w = m.weights[i];
        f[i] = w * cells[m.owner[i]] + (1 - w) * cells[m.neighbour[i]];
    }
    f.tail(m.boundaryFaces) = boundary;
    return f;
}

Eigen::VectorXd div(const FvMesh& m, const Eigen::VectorXd& flux) {
    if (flux.size() != m.faces())
        throw std::invalid_argument("fv div: " + std::to_string(flux.size()) + " face values for " +
                                    std::to_string(m.faces()) + " faces");
    Eigen::VectorXd d = Eigen::VectorXd::Zero(m.cells);
    for (Eigen::Index i = 0; i < m.internalFaces; ++i) {
        d[m.owner[i]] += flux[i];
        d[m.neighbour[i]] -= flux[i];
    }
    for (Eigen::Index i = m.internalFaces; i < m.faces(); ++i) d[m.owner[i]] += flux[i];
    return d.cwiseQuotient(m.V);
}

Vectors grad(const FvMesh& m, const Eigen::VectorXd& cells, const Eigen::VectorXd& boundary) {
    // Gauss: each component is the divergence of the face flux Sf_k phi_f.
    const Eigen::VectorXd f = interpolate(m, cells, boundary);
    Vectors g(m.cells, 3);
    for (int k = 0; k < 3; ++k) g.col(k) = div(m, m.Sf.col(k).cwiseProduct(f));
    return g;
}

Eigen::VectorXd laplacian(const FvMesh& m, const Eigen::VectorXd& cells, const Eigen::VectorXd& boundary) {
    return laplacian(m, Eigen::VectorXd::Ones(m.faces()), cells, boundary);
}

Eigen::VectorXd laplacian(const FvMesh& m, const Eigen::VectorXd& gamma, const Eigen::VectorXd& cells,
                          const Eigen::VectorXd& boundary) {
    if (gamma.size() != m.faces()) throw std::invalid_argument("fv laplacian: diffusivity not given on every face");
    Eigen::VectorXd flux(m.faces());
    for (Eigen::Index i = 0; i < m.internalFaces; ++i)
        flux[i] = gamma[i] * m.magSf[i] * m.deltaCoeffs[i] * (cells[m.neighbour[i]] - cells[m.owner[i]]);
    if (!m.orthogonal) {
        // correctedSnGrad: the orthogonal part plus the correction from the interpolated gradient.
        const Vectors g = grad(m, cells, boundary);
        for (Eigen::Index i = 0; i < m.internalFaces; ++i) {
            const double w = m.weights[i];
            const Eigen::RowVector3d gf = w * g.row(m.owner[i]) + (1 - w) * g.row(m.neighbour[i]);
            flux[i] += gamma[i] * m.magSf[i] * m.corrVecs.row(i).dot(gf);
        }
    }
    for (Eigen::Index i = m.internalFaces; i < m.faces(); ++i)
        flux[i] = gamma[i] * m.magSf[i] * m.deltaCoeffs[i] * (boundary[i - m.internalFaces] - cells[m.owner[i]]);
    return div(m, flux);
}

std::array<Vectors, 3> gradComponents(const FvMesh& m, const Vectors& U, const Vectors& boundaryU) {
    requireSizes(m, U.rows(), boundaryU.rows());
    return {grad(m, U.col(0), boundaryU.col(0)), grad(m, U.col(1), boundaryU.col(1)),
            grad(m, U.col(2), boundaryU.col(2))};
}

Vectors reconstruct(const FvMesh& m, const Eigen::VectorXd& flux) {
    if (flux.size() != m.faces())
        throw std::invalid_argument("fv reconstruct: " + std::to_string(flux.size()) + " face values for " +
                                    std::to_string(m.faces()) + " faces");
    std::vector<Eigen::Matrix3d> t(static_cast<size_t>(m.cells), Eigen::Matrix3d::Zero());
    Vectors s = Vectors::Zero(m.cells, 3);
    for (Eigen::Index i = 0; i < m.faces(); ++i) {
        const Eigen::RowVector3d hat = m.Sf.row(i) / m.magSf[i];
        const Eigen::Matrix3d tt = hat.transpose() * m.Sf.row(i);
        const Eigen::RowVector3d sv = hat * flux[i];
        t[static_cast<size_t>(m.owner[i])] += tt;
        s.row(m.owner[i]) += sv;
        if (i < m.internalFaces) {
            t[static_cast<size_t>(m.neighbour[i])] += tt;
            s.row(m.neighbour[i]) += sv;
        }
    }
    Vectors u(m.cells, 3);
    for (Eigen::Index c = 0; c < m.cells; ++c) {
        Eigen::Matrix3d tc = t[static_cast<size_t>(c)];
        const double scale = tc.trace();
        for (int k = 0; k < 3; ++k)
            if (std::abs(tc(k, k)) < 1e-10 * scale) tc(k, k) = 1;  // no face spans it: 2D's empty direction
        u.row(c) = tc.ldlt().solve(s.row(c).transpose()).transpose();
    }
    return u;
}

Eigen::VectorXd strainRate(const FvMesh& m, const Vectors& U, const Vectors& boundaryU) {
    return strainRate(gradComponents(m, U, boundaryU));
}

Eigen::VectorXd strainRate(const std::array<Vectors, 3>& g) {
    const Eigen::Index cells = g[0].rows();
    Eigen::VectorXd out(cells);
    for (Eigen::Index c = 0; c < cells; ++c) {
        Eigen::Matrix3d t;  // t(i, j) = dU_j / dx_i, as OpenFOAM's grad(U)
        for (int j = 0; j < 3; ++j) t.col(j) = g[static_cast<size_t>(j)].row(c).transpose();
        out[c] = strainRate(t);
    }
    return out;
}

double strainRate(const Eigen::Matrix3d& t) {
    const Eigen::Matrix3d s = 0.5 * (t + t.transpose());
    return std::sqrt(2.0) * std::sqrt((s.array() * s.array()).sum());
}

}  // namespace mixload::rom
