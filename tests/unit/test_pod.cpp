// SPDX-License-Identifier: GPL-3.0-or-later
// POD by the method of snapshots on synthetic snapshots: exact on low-rank data, the same whether
// the snapshots arrive in one block or several, the left-out energy equal to the projection error,
// coupled fields weighted by their energy, bad input refused.
#include <gtest/gtest.h>

#include <random>

#include <set>

#include "rom/hyper/deim.hpp"
#include "rom/hyper/nnls.hpp"
#include "rom/pod/pod.hpp"
#include "rom/regression/pod_regression.hpp"

using namespace mixload::rom;

namespace {
// rows x n snapshots: mean + rank-r part + noise, with positive weights.
struct Data {
    Eigen::MatrixXd x;
    Eigen::VectorXd w;
};

Data synthetic(Eigen::Index rows, Eigen::Index n, Eigen::Index rank, double noise, unsigned seed) {
    std::mt19937 rng(seed);
    std::normal_distribution<double> g;
    const auto rnd = [&](Eigen::Index r, Eigen::Index c) {
        return Eigen::MatrixXd(Eigen::MatrixXd::NullaryExpr(r, c, [&] { return g(rng); }));
    };
    Data d;
    const Eigen::VectorXd mean = rnd(rows, 1);
    d.x = (rnd(rows, rank) * rnd(rank, n)).colwise() + mean;
    d.x += noise * rnd(rows, n);
    d.w = rnd(rows, 1).cwiseAbs().array() + 0.1;
    return d;
}

PodBasis podInBlocks(const Data& d, const std::vector<Eigen::Index>& sizes, const PodOptions& o) {
    std::vector<Eigen::Index> at{0};
    for (auto s : sizes) at.push_back(at.back() + s);
    return computePod(
        sizes.size(), [&](size_t i) { return Eigen::MatrixXd(d.x.middleCols(at[i], sizes[i])); }, d.w, o);
}

double weightedNorm2(const Eigen::VectorXd& v, const Eigen::VectorXd& w) { return v.cwiseProduct(v).dot(w); }
}  // namespace

TEST(Pod, ExactOnLowRankSnapshots) {
    const auto d = synthetic(200, 16, 4, 0.0, 1);
    PodOptions o;
    o.energy = 1.0;
    const auto b = podInBlocks(d, {5, 7, 4}, o);
    EXPECT_EQ(b.snapshots, 16u);
    EXPECT_EQ(b.modes.cols(), 4) << "a rank-4 fluctuation needs 4 modes";
    EXPECT_LT(b.eigenvalues.tail(12).maxCoeff(), 1e-12 * b.eigenvalues[0]);
    EXPECT_LT(b.orthonormalityError(), 1e-12);
    for (Eigen::Index j = 0; j < d.x.cols(); ++j) {
        const Eigen::VectorXd u = d.x.col(j);
        EXPECT_LT((b.reconstruct(b.project(u)) - u).norm(), 1e-10 * u.norm()) << "snapshot " << j;
        EXPECT_LT((b.project(u) - b.coefficients.row(j).transpose()).norm(), 1e-10 * b.project(u).norm());
    }
}

TEST(Pod, BlocksDoNotChangeTheBasis) {
    const auto d = synthetic(150, 12, 12, 0.0, 2);
    PodOptions o;
    o.maxModes = 6;
    const auto one = podInBlocks(d, {12}, o), three = podInBlocks(d, {3, 4, 5}, o);
    ASSERT_EQ(one.modes.cols(), three.modes.cols());
    EXPECT_LT((one.eigenvalues - three.eigenvalues).norm(), 1e-10 * one.eigenvalues.norm());
    // Modes are defined up to sign.
    for (Eigen::Index k = 0; k < one.modes.cols(); ++k) {
        const double s = one.modes.col(k).dot(three.modes.col(k)) > 0 ? 1 : -1;
        EXPECT_LT((one.modes.col(k) - s * three.modes.col(k)).norm(), 1e-8 * one.modes.col(k).norm()) << k;
    }
    // Two blocks are held at a time, not all of them.
    EXPECT_LT(three.peakBytes, one.peakBytes);
}

TEST(Pod, LeftOutEnergyIsTheProjectionError) {
    const auto d = synthetic(300, 20, 20, 0.0, 3);
    for (int k : {1, 5, 12}) {
        PodOptions o;
        o.maxModes = k;
        o.energy = 1.0;
        const auto b = podInBlocks(d, {7, 7, 6}, o);
        ASSERT_EQ(b.modes.cols(), k);
        double err = 0;
        for (Eigen::Index j = 0; j < d.x.cols(); ++j) {
            const Eigen::VectorXd u = d.x.col(j);
            err += weightedNorm2(u - b.reconstruct(b.project(u)), b.weights);
        }
        const double left = b.eigenvalues.tail(b.eigenvalues.size() - k).sum();
        EXPECT_NEAR(err, left, 1e-9 * b.totalEnergy()) << k << " modes";
        EXPECT_NEAR(b.keptEnergy(), 1 - left / b.totalEnergy(), 1e-12);
    }
}

TEST(Pod, EnergyTargetPicksTheFewestModes) {
    const auto d = synthetic(100, 15, 15, 0.0, 4);
    PodOptions o;
    o.energy = 0.9;
    const auto b = podInBlocks(d, {15}, o);
    EXPECT_GE(b.keptEnergy(), 0.9);
    const auto k = b.modes.cols();
    EXPECT_LT(b.eigenvalues.head(k - 1).sum() / b.totalEnergy(), 0.9);
}

TEST(Pod, CoupledFieldsCarryTheSameEnergy) {
    // Two fields whose scales differ by 1e3: uncoupled weights would let the large one take every mode.
    auto d = synthetic(120, 10, 10, 0.0, 5);
    d.x.bottomRows(60) *= 1e3;
    PodOptions o;
    o.energy = 1.0;
    o.fieldStarts = {0, 60};
    const auto b = podInBlocks(d, {10}, o);
    ASSERT_EQ(b.fieldScales.size(), 2u);
    EXPECT_NEAR(b.fieldScales[1] / b.fieldScales[0], 1e6, 2e5);
    double e0 = 0, e1 = 0;
    for (Eigen::Index j = 0; j < d.x.cols(); ++j) {
        const Eigen::VectorXd f = d.x.col(j) - b.mean;
        e0 += weightedNorm2(f.head(60), b.weights.head(60));
        e1 += weightedNorm2(f.tail(60), b.weights.tail(60));
    }
    EXPECT_NEAR(e0, 1.0, 1e-10);
    EXPECT_NEAR(e1, 1.0, 1e-10);
}

TEST(Pod, BadInputIsRefused) {
    const auto d = synthetic(10, 4, 2, 0.0, 6);
    EXPECT_THROW(computePod(0, [&](size_t) { return d.x; }, d.w, {}), std::invalid_argument);
    EXPECT_THROW(computePod(1, [&](size_t) { return Eigen::MatrixXd(d.x.topRows(5)); }, d.w, {}),
                 std::invalid_argument);
}

TEST(Deim, ExactInTheSpanOfItsBasisWithDistinctPoints) {
    const auto d = synthetic(80, 6, 6, 0.0, 7);
    const Eigen::MatrixXd q = d.x.householderQr().householderQ() * Eigen::MatrixXd::Identity(80, 6);
    const auto deim = buildDeim(q);
    ASSERT_EQ(deim.points.size(), 6u);
    EXPECT_EQ(std::set<Eigen::Index>(deim.points.begin(), deim.points.end()).size(), 6u);
    const Eigen::VectorXd f = q * Eigen::VectorXd::LinSpaced(6, 1, 6);
    EXPECT_LT(deim.relativeError(f), 1e-12);
    // Outside the span the error is what the basis misses, amplified by at most ||(P^T U)^-1||.
    const Eigen::VectorXd g = Eigen::VectorXd::Ones(80);
    const Eigen::VectorXd miss = g - q * (q.transpose() * g);
    EXPECT_LE(deim.relativeError(g) * g.norm(), (1 + deim.pInverse.norm()) * miss.norm() + 1e-12);
    EXPECT_THROW(buildDeim(Eigen::MatrixXd(q.leftCols(2).replicate(1, 2))), std::invalid_argument);
}

TEST(SparseNnls, FindsTheNonNegativeOptimumAndStopsAtItsTolerance) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(0, 1);
    Eigen::MatrixXd G(60, 25);
    for (Eigen::Index i = 0; i < G.size(); ++i) G.data()[i] = u(rng);
    // A target made of three columns with positive weights: recovered exactly, nothing else active.
    Eigen::VectorXd w = Eigen::VectorXd::Zero(25);
    w[3] = 2.0, w[11] = 0.5, w[20] = 1.25;
    Eigen::VectorXd y = G * w;
    auto s = mixload::rom::sparseNnls(G.transpose() * G, G.transpose() * y, y.squaredNorm(), 1e-10, 25);
    ASSERT_EQ(s.columns.size(), 3u);
    for (size_t i = 0; i < 3; ++i) EXPECT_NEAR(s.weights[static_cast<Eigen::Index>(i)], w[s.columns[i]], 1e-8);
    EXPECT_LT(s.relativeResidual, 1e-10);
    // A target whose unconstrained fit needs negative weights: every weight stays positive, and the
    // residual is what the non-negative optimum leaves (its gradient has no ascent direction left).
    y = G.col(0) - 0.8 * G.col(1) + 0.3 * G.col(2);
    s = mixload::rom::sparseNnls(G.transpose() * G, G.transpose() * y, y.squaredNorm(), 1e-12, 25);
    EXPECT_GT(s.weights.minCoeff(), 0.0);
    Eigen::VectorXd full = Eigen::VectorXd::Zero(25);
    for (size_t i = 0; i < s.columns.size(); ++i) full[s.columns[i]] = s.weights[static_cast<Eigen::Index>(i)];
    EXPECT_LT((G.transpose() * (y - G * full)).maxCoeff(), 1e-8 * y.norm());
    EXPECT_GT(s.relativeResidual, 1e-3);
    // On the three-column target: capped at two columns it stops there, short of exact; with that
    // residual as its tolerance it stops as early, within it.
    y = G * w;
    const auto capped = mixload::rom::sparseNnls(G.transpose() * G, G.transpose() * y, y.squaredNorm(), 1e-10, 2);
    EXPECT_LE(capped.columns.size(), 2u);
    EXPECT_GT(capped.relativeResidual, 1e-6);
    const double tol = capped.relativeResidual * 1.001;
    const auto loose = mixload::rom::sparseNnls(G.transpose() * G, G.transpose() * y, y.squaredNorm(), tol, 25);
    EXPECT_LE(loose.relativeResidual, tol);
    EXPECT_LE(loose.columns.size(), 2u);
}

TEST(PodRegression, ReproducesItsRunsAndInterpolatesASmoothFamily) {
    // Fields f(x) = b0 + x0 b1 + x0 x1 b2 on 12 runs in [0, 1]^2: three modes span them.
    const Eigen::Index rows = 50, runs = 12;
    Eigen::MatrixXd b = Eigen::MatrixXd::Random(rows, 3);
    Eigen::MatrixXd X(runs, 2), F(rows, runs);
    for (Eigen::Index i = 0; i < runs; ++i) {
        X(i, 0) = (i % 4) / 3.0;
        X(i, 1) = (i / 4) / 2.0;
        F.col(i) = b.col(0) + X(i, 0) * b.col(1) + X(i, 0) * X(i, 1) * b.col(2);
    }
    const auto r = mixload::rom::PodRegression::fit(X, F, Eigen::VectorXd::Ones(rows), 0);
    EXPECT_LE(r.modes(), 3);
    for (Eigen::Index i = 0; i < runs; ++i)
        EXPECT_LT((r.predict(X.row(i).transpose()) - F.col(i)).norm(), 1e-3 * F.col(i).norm()) << i;
    const Eigen::Vector2d x(0.5, 0.6);
    const Eigen::VectorXd exact = b.col(0) + x[0] * b.col(1) + x[0] * x[1] * b.col(2);
    EXPECT_LT((r.predict(x) - exact).norm(), 0.05 * exact.norm());
    EXPECT_THROW(mixload::rom::PodRegression::fit(X.topRows(3), F, Eigen::VectorXd::Ones(rows), 0), std::invalid_argument);
}
