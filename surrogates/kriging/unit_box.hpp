// SPDX-License-Identifier: GPL-3.0-or-later
// Inputs scaled to their training box, [0, 1] per input: the units in which a kriging model is fitted
// (its length-scale bounds are set in them). A constant input keeps a unit span, so it maps to 0.
#pragma once

#include <Eigen/Dense>

namespace mixload::surrogates {

struct UnitBox {
    Eigen::VectorXd lo, span;

    // The box of the rows of X (one point per row).
    static UnitBox of(const Eigen::MatrixXd& X) {
        UnitBox b;
        b.lo = X.colwise().minCoeff().transpose();
        b.span = (X.colwise().maxCoeff().transpose() - b.lo).cwiseMax(1e-12);
        return b;
    }
    Eigen::VectorXd operator()(const Eigen::VectorXd& x) const { return (x - lo).cwiseQuotient(span); }
    Eigen::MatrixXd rows(const Eigen::MatrixXd& X) const {
        return (X.rowwise() - lo.transpose()).array().rowwise() / span.transpose().array();
    }
};

}  // namespace mixload::surrogates
