// SPDX-License-Identifier: GPL-3.0-or-later
// Discrete empirical interpolation (Chaturantabut & Sorensen 2010): a nonlinear field (here the
// mu(I) viscosity) reconstructed from its values at a few cells, f ~ U (P^T U)^-1 P^T f, with U a POD
// basis of the field's snapshots and P the cells picked greedily where the basis interpolates
// worst. A reduced model then evaluates the law only at those cells (and the neighbours their
// gradients need), not on the whole mesh.
#pragma once
#include <vector>

#include <Eigen/Dense>

namespace mixload::rom {

struct Deim {
    Eigen::MatrixXd basis;              // rows x m
    std::vector<Eigen::Index> points;   // m distinct rows
    Eigen::MatrixXd pInverse;           // (P^T U)^-1, m x m

    // The whole field from its values at the points.
    Eigen::VectorXd reconstruct(const Eigen::VectorXd& atPoints) const;
    Eigen::VectorXd sample(const Eigen::VectorXd& field) const;
    // || f - reconstruct(sample(f)) || / || f || (Euclidean, or weighted by w when given).
    double relativeError(const Eigen::VectorXd& f, const Eigen::VectorXd& w = {}) const;
};

// basis: rows x m, linearly independent columns (a POD basis). Throws std::invalid_argument when the
// greedy selection meets a column already interpolated exactly (dependent columns).
Deim buildDeim(const Eigen::MatrixXd& basis);

}  // namespace mixload::rom
