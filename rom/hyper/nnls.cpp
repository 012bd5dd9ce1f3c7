// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/hyper/nnls.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace mixload::rom {

namespace {
// Unconstrained least squares on the active columns, from the normal equations.
Eigen::VectorXd solveOn(const Eigen::MatrixXd& gram, const Eigen::VectorXd& gy, const std::vector<Eigen::Index>& cols) {
    const auto n = static_cast<Eigen::Index>(cols.size());
    Eigen::MatrixXd a(n, n);
    Eigen::VectorXd b(n);
    for (Eigen::Index i = 0; i < n; ++i) {
        b[i] = gy[cols[static_cast<size_t>(i)]];
        for (Eigen::Index j = 0; j < n; ++j) a(i, j) = gram(cols[static_cast<size_t>(i)], cols[static_cast<size_t>(j)]);
    }
    return a.ldlt().solve(b);
}
}  // namespace

SparseNnls sparseNnls(const Eigen::MatrixXd& gram, const Eigen::VectorXd& gy, double yy, double tolerance,
                      Eigen::Index maxColumns) {
    const Eigen::Index n = gy.size();
    if (gram.rows() != n || gram.cols() != n) throw std::invalid_argument("nnls: G^T G and G^T y disagree in size");
    if (!(yy > 0)) throw std::invalid_argument("nnls: the target is zero");
    Eigen::VectorXd w = Eigen::VectorXd::Zero(n);
    std::vector<Eigen::Index> active;
    std::vector<bool> isActive(static_cast<size_t>(n), false);
    const auto residual2 = [&] { return std::max(yy - 2 * w.dot(gy) + w.dot(gram * w), 0.0); };
    while (residual2() > tolerance * tolerance * yy && static_cast<Eigen::Index>(active.size()) < maxColumns) {
        // The column whose weight would lower the residual fastest.
        const Eigen::VectorXd grad = gy - gram * w;
        Eigen::Index best = -1;
        double top = 0;
        for (Eigen::Index j = 0; j < n; ++j)
            if (!isActive[static_cast<size_t>(j)] && grad[j] > top) top = grad[j], best = j;
        if (best < 0) break;  // no column lowers it: the non-negative optimum
        active.push_back(best);
        isActive[static_cast<size_t>(best)] = true;
        for (;;) {
            const Eigen::VectorXd s = solveOn(gram, gy, active);
            if (s.minCoeff() > 0) {
                for (size_t i = 0; i < active.size(); ++i) w[active[i]] = s[static_cast<Eigen::Index>(i)];
                break;
            }
            // Step from w towards s until the first weight reaches zero; drop the zeros.
            double step = 1;
            for (size_t i = 0; i < active.size(); ++i) {
                const double wi = w[active[i]], si = s[static_cast<Eigen::Index>(i)];
                if (si <= 0) step = std::min(step, wi / (wi - si));
            }
            std::vector<Eigen::Index> kept;
            for (size_t i = 0; i < active.size(); ++i) {
                const Eigen::Index j = active[i];
                w[j] += step * (s[static_cast<Eigen::Index>(i)] - w[j]);
                if (w[j] > 1e-14 * std::max(1.0, w.cwiseAbs().maxCoeff())) kept.push_back(j);
                else w[j] = 0, isActive[static_cast<size_t>(j)] = false;
            }
            active = kept;
            if (active.empty()) break;
        }
    }
    SparseNnls out;
    out.columns = active;
    out.weights.resize(static_cast<Eigen::Index>(active.size()));
    for (size_t i = 0; i < active.size(); ++i) out.weights[static_cast<Eigen::Index>(i)] = w[active[i]];
    out.relativeResidual = std::sqrt(residual2() / yy);
    return out;
}

}  // namespace mixload::rom
