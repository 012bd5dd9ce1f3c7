// SPDX-License-Identifier: GPL-3.0-or-later
// SUNDIALS CVODE (variable-order BDF, Newton iterations on a dense difference-quotient Jacobian)
// for the small stiff systems of reduced models. The viscous terms of a mu(I) flow are stiff (the
// capped viscosity of powder at rest), which rules out explicit schemes at the steps the transport
// allows. Errors thrown by the right-hand side cross CVODE's C code as a failure flag and are
// rethrown unchanged.
#pragma once

#include <functional>
#include <memory>

#include <Eigen/Dense>

namespace mixload::rom {

class CvodeIntegrator {
  public:
    using Rhs = std::function<void(double t, const Eigen::VectorXd& y, Eigen::VectorXd& dydt)>;
    using Jacobian = std::function<void(double t, const Eigen::VectorXd& y, Eigen::MatrixXd& dfdy)>;

    // rtol: relative tolerance; atol: absolute tolerance per component (size n).
    CvodeIntegrator(Eigen::Index n, Rhs rhs, double rtol, const Eigen::VectorXd& atol);
    ~CvodeIntegrator();
    // The right-hand side's Jacobian, instead of CVODE's difference quotients (n evaluations each).
    void setJacobian(Jacobian jacobian);
    CvodeIntegrator(const CvodeIntegrator&) = delete;
    CvodeIntegrator& operator=(const CvodeIntegrator&) = delete;

    // Integrates y from t to tOut. With restart, CVODE's history starts again at (t, y) (order 1, a
    // new Jacobian); without, it goes on from where the last advance ended (y and t must be what it
    // returned), which is far cheaper when what the right-hand side depends on changes only a little
    // between advances. Throws std::runtime_error naming CVODE's failure.
    void advance(double t, double tOut, Eigen::VectorXd& y, bool restart = true);

    long steps() const;        // internal steps taken, summed over every advance
    long rhsEvaluations() const;       // including the difference quotients of the Jacobian, if any
    long jacobianEvaluations() const;

  private:
    struct State;
    std::unique_ptr<State> s_;
};

}  // namespace mixload::rom
