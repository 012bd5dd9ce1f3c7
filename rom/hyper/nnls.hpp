// SPDX-License-Identifier: GPL-3.0-or-later
// Sparse non-negative least squares for empirical cubature: Lawson & Hanson's active-set method,
// stopped as soon as the residual meets a tolerance, so that the few columns it has activated are
// the cubature points and their coefficients the positive weights (energy-conserving sampling and
// weighting, Farhat, Chapman & Avery 2015). Works on the normal equations (G^T G, G^T y) because the
// columns number in the thousands and the rows in the tens of thousands.
#pragma once
#include <vector>

#include <Eigen/Dense>

namespace mixload::rom {

struct SparseNnls {
    std::vector<Eigen::Index> columns;  // the active columns
    Eigen::VectorXd weights;            // their coefficients, all > 0
    double relativeResidual = 0;        // ||G w - y|| / ||y||
};

// min ||G w - y|| over w >= 0, stopped once the relative residual is <= tolerance or maxColumns
// are active (gram = G^T G, gy = G^T y, yy = y^T y).
SparseNnls sparseNnls(const Eigen::MatrixXd& gram, const Eigen::VectorXd& gy, double yy, double tolerance,
                      Eigen::Index maxColumns);

}  // namespace mixload::rom
