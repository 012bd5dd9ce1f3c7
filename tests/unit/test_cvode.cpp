// SPDX-License-Identifier: GPL-3.0-or-later
// The CVODE wrapper (rom/galerkin/cvode_integrator): a stiff linear system against its exact solution,
// restarts between advances, and an error thrown by the right-hand side reaching the caller.
#include <gtest/gtest.h>

#include <cmath>

#include "rom/galerkin/cvode_integrator.hpp"

using namespace mixload::rom;

TEST(Cvode, StiffLinearSystemMatchesItsExactSolution) {
    // y0' = -1000 (y0 - cos t), y1' = -y1: a fast and a slow decay.
    CvodeIntegrator ode(
        2,
        [](double t, const Eigen::VectorXd& y, Eigen::VectorXd& dy) {
            dy.resize(2);
            dy << -1000 * (y[0] - std::cos(t)), -y[1];
        },
        1e-8, Eigen::VectorXd::Constant(2, 1e-12));
    Eigen::VectorXd y(2);
    y << 0, 1;
    double t = 0;
    for (int k = 1; k <= 4; ++k) {  // four advances, each restarting CVODE's history
        ode.advance(t, 0.5 * k, y);
        t = 0.5 * k;
    }
    // The stiff component follows cos t with a lag ~ sin(t)/1000.
    EXPECT_NEAR(y[0], std::cos(2.0) + std::sin(2.0) / 1000.0, 1e-5);
    EXPECT_NEAR(y[1], std::exp(-2.0), 1e-6);
    EXPECT_GT(ode.steps(), 0);
    // A stiff problem: an implicit method needs far fewer steps than 1000 * 2 / 2 explicit ones.
    EXPECT_LT(ode.steps(), 500);
}

TEST(Cvode, AnErrorInTheRightHandSideReachesTheCaller) {
    CvodeIntegrator ode(
        1,
        [](double t, const Eigen::VectorXd&, Eigen::VectorXd& dy) {
            if (t > 0.1) throw std::domain_error("model left its bounds");
            dy = Eigen::VectorXd::Constant(1, 1.0);
        },
        1e-6, Eigen::VectorXd::Constant(1, 1e-10));
    Eigen::VectorXd y = Eigen::VectorXd::Zero(1);
    EXPECT_THROW(ode.advance(0, 1, y), std::domain_error);
}
