// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/pod/pod.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace mixload::rom {

double PodBasis::keptEnergy() const {
    const double total = totalEnergy();
    return total > 0 ? eigenvalues.head(modes.cols()).sum() / total : 1.0;
}

Eigen::VectorXd PodBasis::project(const Eigen::VectorXd& u) const {
    return modes.transpose() * weights.cwiseProduct(u - mean);
}

double PodBasis::orthonormalityError() const {
    const Eigen::MatrixXd g = modes.transpose() * weights.asDiagonal() * modes;
    return (g - Eigen::MatrixXd::Identity(g.rows(), g.cols())).cwiseAbs().maxCoeff();
}

PodBasis computePod(size_t blocks, const std::function<Eigen::MatrixXd(size_t)>& block,
                    const Eigen::VectorXd& weights, const PodOptions& o) {
    if (blocks == 0) throw std::invalid_argument("POD: no snapshots");
    const Eigen::Index rows = weights.size();
    std::vector<Eigen::Index> starts = o.fieldStarts.empty() ? std::vector<Eigen::Index>{0} : o.fieldStarts;
    starts.push_back(rows);
    PodBasis b;
    double peak = 0;
    const auto held = [&](double bytes) { peak = std::max(peak, bytes); };
    const auto fetch = [&](size_t i) {
        Eigen::MatrixXd x = block(i);
        if (x.rows() != rows)
            throw std::invalid_argument("POD: block " + std::to_string(i) + " has " + std::to_string(x.rows()) +
                                        " rows, the weights " + std::to_string(rows));
        return x;
    };

    // Pass 1: the mean, each field's weighted energy sum_j |x_j|^2, the block sizes.
    std::vector<Eigen::Index> offset{0};
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(rows);
    std::vector<double> squares(starts.size() - 1, 0.0);
    for (size_t i = 0; i < blocks; ++i) {
        const Eigen::MatrixXd x = fetch(i);
        held(8.0 * x.size());
        sum += x.rowwise().sum();
        for (size_t f = 0; f + 1 < starts.size(); ++f) {
            const auto n = starts[f + 1] - starts[f];
            squares[f] += (x.middleRows(starts[f], n).array().square().colwise() *
                           weights.segment(starts[f], n).array())
                              .sum();
        }
        offset.push_back(offset.back() + x.cols());
    }
    const Eigen::Index n = offset.back();
    if (n == 0) throw std::invalid_argument("POD: no snapshots");
    b.snapshots = static_cast<size_t>(n);
    b.mean = o.subtractMean ? Eigen::VectorXd(sum / double(n)) : Eigen::VectorXd::Zero(rows);
    b.weights = weights;
    for (size_t f = 0; f + 1 < starts.size(); ++f) {
        const auto len = starts[f + 1] - starts[f];
        const auto m = b.mean.segment(starts[f], len);
        // sum_j |x_j - m|^2 = sum_j |x_j|^2 - n |m|^2 (weighted)
        const double energy = squares[f] - double(n) * (m.array().square() * weights.segment(starts[f], len).array()).sum();
        const double scale = starts.size() > 2 && energy > 0 ? energy : 1.0;
        b.fieldScales.push_back(scale);
        b.weights.segment(starts[f], len) /= scale;
    }

    // Pass 2: the Gram matrix C = X^T W X, block pair by block pair.
    Eigen::MatrixXd c(n, n);
    for (size_t i = 0; i < blocks; ++i) {
        const Eigen::MatrixXd wx = b.weights.asDiagonal() * (fetch(i).colwise() - b.mean);
        const auto ni = offset[i + 1] - offset[i];
        for (size_t j = 0; j <= i; ++j) {
            const Eigen::MatrixXd xj = j == i ? Eigen::MatrixXd(fetch(i).colwise() - b.mean)
                                              : Eigen::MatrixXd(fetch(j).colwise() - b.mean);
            held(8.0 * (wx.size() + xj.size() + double(n) * n));
            const Eigen::MatrixXd cij = xj.transpose() * wx;  // n_j x n_i
            c.block(offset[j], offset[i], offset[j + 1] - offset[j], ni) = cij;
            c.block(offset[i], offset[j], ni, offset[j + 1] - offset[j]) = cij.transpose();
        }
    }

    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(c);
    if (es.info() != Eigen::Success) throw std::runtime_error("POD: the eigen-solver of the Gram matrix failed");
    b.eigenvalues = es.eigenvalues().reverse().cwiseMax(0.0);
    const Eigen::MatrixXd v = es.eigenvectors().rowwise().reverse();

    // Modes kept: the energy share, the cap, and never a numerically null one (its mode would be
    // round-off divided by a tiny sqrt(lambda)).
    const double total = b.eigenvalues.sum();
    Eigen::Index k = 0;
    double acc = 0;
    while (k < n && b.eigenvalues[k] > 1e-12 * b.eigenvalues[0] && (o.maxModes <= 0 || k < o.maxModes)) {
        acc += b.eigenvalues[k];
        ++k;
        if (total <= 0 || acc >= o.energy * total) break;
    }

    // Pass 3: Phi = X V_k Lambda_k^(-1/2), summed block by block.
    b.modes = Eigen::MatrixXd::Zero(rows, k);
    const Eigen::VectorXd invSqrt = b.eigenvalues.head(k).cwiseSqrt().cwiseInverse();
    for (size_t i = 0; i < blocks && k > 0; ++i) {
        const Eigen::MatrixXd x = fetch(i).colwise() - b.mean;
        held(8.0 * (x.size() + double(n) * n + double(rows) * k));
        b.modes += x * (v.block(offset[i], 0, offset[i + 1] - offset[i], k) * invSqrt.asDiagonal());
    }
    b.coefficients = v.leftCols(k) * b.eigenvalues.head(k).cwiseSqrt().asDiagonal();
    // Round-off grows as lambda_0 / lambda_k; one Cholesky step restores orthonormality to
    // round-off, and the coefficients follow (Phi_new = Phi L^-T, so a_new = L^T a).
    if (k > 0) {
        const Eigen::MatrixXd g = b.modes.transpose() * b.weights.asDiagonal() * b.modes;
        const Eigen::LLT<Eigen::MatrixXd> llt(g);
        if (llt.info() == Eigen::Success) {
            const Eigen::MatrixXd l = llt.matrixL();
            b.modes = l.triangularView<Eigen::Lower>().solve(b.modes.transpose()).transpose();
            b.coefficients = b.coefficients * l;
        }
    }
    b.peakBytes = peak + 8.0 * (3.0 * rows);
    return b;
}

}  // namespace mixload::rom
