// SPDX-License-Identifier: GPL-3.0-or-later
// Quadratic response surface in scaled inputs z in [-1, 1]^d: intercept, linear, square and
// interaction terms, fitted by GSL least squares, with forward term selection by PRESS.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

namespace mixload::surrogates {

// A term z_i * z_j; i = j = -1 is the intercept, j = -1 a linear term.
struct Term {
    int i = -1, j = -1;
    double eval(const double* z) const {
        return i < 0 ? 1.0 : j < 0 ? z[i] : z[i] * z[j];
    }
    std::string name(const std::vector<std::string>& inputs) const;
};

std::vector<Term> fullQuadratic(int d);

class ResponseSurface {
public:
    // select: forward selection by PRESS from the intercept (stops when no term lowers PRESS or
    // when n - p would fall below 2); otherwise every term of the full quadratic.
    static ResponseSurface fit(const Eigen::MatrixXd& Z, const Eigen::VectorXd& y, bool select);
    static ResponseSurface fitTerms(const Eigen::MatrixXd& Z, const Eigen::VectorXd& y,
                                    const std::vector<Term>& terms);

    // Leave-one-out of the whole procedure: each run is predicted by a surface whose terms were
    // selected without it. The closed-form residuals of a selected surface are optimistic (the
    // terms were chosen to make them small); with few runs and 36 candidates, by a factor of
    // several. Returns y_i - yhat_{-i} and the variance of a new observation at run i.
    struct Loo {
        Eigen::VectorXd residuals, variances;
    };
    static Loo selectedLoo(const Eigen::MatrixXd& Z, const Eigen::VectorXd& y);

    int dims() const { return dims_; }
    const std::vector<Term>& terms() const { return terms_; }
    const Eigen::VectorXd& coefficients() const { return coef_; }
    Eigen::VectorXd standardErrors() const;
    double press() const { return press_; }
    double residualVariance() const { return s2_; }  // chisq / (n - p)
    int dof() const { return dof_; }
    const Eigen::VectorXd& looResiduals() const { return loo_; }  // y_i - yhat_{-i}
    const Eigen::VectorXd& leverages() const { return leverage_; }  // h_ii (not stored in files)

    // Allocation-free; scratch needs terms().size() doubles.
    double predict(const double* z) const;
    // Mean and the variance of a new observation (s^2 (1 + f^T (X^T X)^-1 f)).
    void predict(const double* z, double* scratch, double& mean, double& variance) const;
    // Means at two points and the covariance of their mean's errors, s^2 f1^T (X^T X)^-1 f2 (the
    // new observations' own s^2 not added). Allocates.
    void predictPair(const double* z1, const double* z2, Eigen::Vector2d& mean, Eigen::Matrix2d& cov) const;

    nlohmann::json toJson() const;
    static ResponseSurface fromJson(const nlohmann::json& j);

private:
    int dims_ = 0, dof_ = 0;
    std::vector<Term> terms_;
    Eigen::VectorXd coef_, loo_, leverage_;
    Eigen::MatrixXd xtxInv_;  // (X^T X)^-1
    double press_ = 0, s2_ = 0;
};

}  // namespace mixload::surrogates
