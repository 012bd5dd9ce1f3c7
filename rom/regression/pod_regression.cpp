// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/regression/pod_regression.hpp"

#include <stdexcept>

namespace mixload::rom {

PodRegression PodRegression::fit(const Eigen::MatrixXd& X, const Eigen::MatrixXd& fields, const Eigen::VectorXd& weights,
                                 int modes, double energy) {
    if (X.rows() != fields.cols() || X.rows() < 2)
        throw std::invalid_argument("POD regression: one input row per field column, at least two");
    PodRegression r;
    r.box_ = surrogates::UnitBox::of(X);
    PodOptions o;
    o.maxModes = modes;
    o.energy = modes > 0 ? 1.0 : energy;
    o.subtractMean = true;
    r.basis_ = computePod(1, [&](size_t) { return fields; }, weights, o);
    const Eigen::MatrixXd Xs = r.box_.rows(X);
    surrogates::KrigingOptions ko;
    for (Eigen::Index k = 0; k < r.basis_.modes.cols(); ++k)
        r.coefficient_.push_back(surrogates::Kriging::fit(Xs, r.basis_.coefficients.col(k), ko));
    return r;
}

Eigen::VectorXd PodRegression::predict(const Eigen::VectorXd& x) const {
    const Eigen::VectorXd xs = box_(x);
    Eigen::VectorXd a(basis_.modes.cols());
    for (size_t k = 0; k < coefficient_.size(); ++k) {
        auto ws = coefficient_[k].makeWorkspace();
        a[static_cast<Eigen::Index>(k)] = coefficient_[k].predictMean(xs.data(), ws);
    }
    return basis_.reconstruct(a);
}

}  // namespace mixload::rom
