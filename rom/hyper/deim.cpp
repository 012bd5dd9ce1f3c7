// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/hyper/deim.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace mixload::rom {

Eigen::VectorXd Deim::sample(const Eigen::VectorXd& f) const {
    Eigen::VectorXd s(static_cast<Eigen::Index>(points.size()));
    for (size_t i = 0; i < points.size(); ++i) s[static_cast<Eigen::Index>(i)] = f[points[i]];
    return s;
}

Eigen::VectorXd Deim::reconstruct(const Eigen::VectorXd& atPoints) const { return basis * (pInverse * atPoints); }

double Deim::relativeError(const Eigen::VectorXd& f, const Eigen::VectorXd& w) const {
    const Eigen::VectorXd e = f - reconstruct(sample(f));
    if (w.size() == 0) return e.norm() / std::max(f.norm(), 1e-300);
    return std::sqrt(e.cwiseProduct(e).dot(w) / std::max(f.cwiseProduct(f).dot(w), 1e-300));
}

Deim buildDeim(const Eigen::MatrixXd& u) {
    if (u.cols() == 0 || u.rows() < u.cols()) throw std::invalid_argument("DEIM: need 1 <= modes <= rows");
    Deim d;
    d.basis = u;
    Eigen::Index p;
    u.col(0).cwiseAbs().maxCoeff(&p);
    d.points.push_back(p);
    for (Eigen::Index j = 1; j < u.cols(); ++j) {
        // Interpolate column j from the points so far; the next point is where that fails worst.
        const Eigen::Index m = j;
        Eigen::MatrixXd pu(m, m);
        Eigen::VectorXd pj(m);
        for (Eigen::Index i = 0; i < m; ++i) {
            pu.row(i) = u.block(d.points[static_cast<size_t>(i)], 0, 1, m);
            pj[i] = u(d.points[static_cast<size_t>(i)], j);
        }
        const Eigen::VectorXd c = pu.partialPivLu().solve(pj);
        const Eigen::VectorXd r = u.col(j) - u.leftCols(m) * c;
        const double worst = r.cwiseAbs().maxCoeff(&p);
        if (!(worst > 1e-12 * u.col(j).cwiseAbs().maxCoeff()))
            throw std::invalid_argument("DEIM: column " + std::to_string(j) + " is interpolated exactly by the earlier ones");
        d.points.push_back(p);
    }
    Eigen::MatrixXd pu(u.cols(), u.cols());
    for (Eigen::Index i = 0; i < u.cols(); ++i) pu.row(i) = u.row(d.points[static_cast<size_t>(i)]);
    d.pInverse = pu.inverse();
    return d;
}

}  // namespace mixload::rom
