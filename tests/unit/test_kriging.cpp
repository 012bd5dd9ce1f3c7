// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <random>
#include <stdexcept>
#include <string>

#include "kriging/kriging.hpp"

#include "alloc_counter.hpp"


using namespace mixload::surrogates;

namespace {

// Points in [0,1]^d from mt19937's raw output (its sequence is fixed by the standard).
Eigen::MatrixXd randomPoints(int n, int d, unsigned seed) {
    std::mt19937 gen(seed);
    Eigen::MatrixXd X(n, d);
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < d; ++k) X(i, k) = (static_cast<double>(gen()) + 0.5) / 4294967296.0;
    return X;
}

double smooth(const Eigen::RowVectorXd& x) { return std::sin(3.0 * x[0]) + x[1] * x[1]; }

Eigen::VectorXd evaluate(const Eigen::MatrixXd& X) {
    Eigen::VectorXd y(X.rows());
    for (int i = 0; i < X.rows(); ++i) y[i] = smooth(X.row(i));
    return y;
}

std::pair<double, double> predictAt(const Kriging& m, const Eigen::RowVectorXd& x) {
    auto ws = m.makeWorkspace();
    const Eigen::VectorXd xc = x.transpose();
    double mean = 0, var = 0;
    m.predict(xc.data(), ws, mean, var);
    return {mean, var};
}

Eigen::MatrixXd withoutRow(const Eigen::MatrixXd& M, int r) {
    Eigen::MatrixXd out(M.rows() - 1, M.cols());
    for (int i = 0, o = 0; i < M.rows(); ++i)
        if (i != r) out.row(o++) = M.row(i);
    return out;
}

Eigen::VectorXd withoutEntry(const Eigen::VectorXd& v, int r) {
    Eigen::VectorXd out(v.size() - 1);
    for (int i = 0, o = 0; i < v.size(); ++i)
        if (i != r) out[o++] = v[i];
    return out;
}

void expectInterpolates(const Kriging& m, const Eigen::MatrixXd& X, const Eigen::VectorXd& y,
                        const std::string& what) {
    SCOPED_TRACE(what);
    const double scale = y.cwiseAbs().maxCoeff();
    for (int i = 0; i < X.rows(); ++i) {
        const auto [mean, var] = predictAt(m, X.row(i));
        EXPECT_NEAR(mean, y[i], 1e-8 * scale) << "point " << i;
        EXPECT_LT(var, 1e-8 * m.processVariance()) << "point " << i;
    }
    // Variance grows away from the data: far outside the box it tends to the prior, and a midpoint
    // between two training points is uncertain.
    const Eigen::RowVectorXd nearPoint = X.row(0).array() + 0.01;
    const Eigen::RowVectorXd farPoint = Eigen::RowVectorXd::Constant(X.cols(), 3.0);
    const Eigen::RowVectorXd mid = 0.5 * (X.row(0) + X.row(1));
    EXPECT_GT(predictAt(m, farPoint).second, predictAt(m, nearPoint).second);
    EXPECT_GT(predictAt(m, mid).second, 0.0);
}

}  // namespace

TEST(Kriging, StringConversions) {
    for (auto k : {Kernel::Matern52, Kernel::SquaredExponential}) EXPECT_EQ(kernelFromString(toString(k)), k);
    for (auto t : {Trend::Constant, Trend::Linear}) EXPECT_EQ(trendFromString(toString(t)), t);
    EXPECT_THROW(kernelFromString("gauss"), std::invalid_argument);
    EXPECT_THROW(trendFromString("quadratic"), std::invalid_argument);
}

TEST(Kriging, InterpolatesTrainingDataWithoutNugget) {
    const Eigen::MatrixXd X = randomPoints(15, 2, 7);
    const Eigen::VectorXd y = evaluate(X);
    const Eigen::Vector2d ls(0.3, 0.4);
    for (auto k : {Kernel::Matern52, Kernel::SquaredExponential})
        for (auto t : {Trend::Constant, Trend::Linear}) {
            // Matern 5/2 factorises with no nugget at all; the squared exponential needs jitter.
            const double g = k == Kernel::Matern52 ? 0.0 : 1e-12;
            const auto m = Kriging::withHyperparameters(X, y, k, t, ls, g);
            expectInterpolates(m, X, y, toString(k) + "/" + toString(t));
        }

    KrigingOptions o;
    o.estimateNugget = false;
    o.nugget = 0.0;  // even 1e-12 shifts the mean by g * alpha_i, visible at 1e-8 once alpha is large
    o.starts = 5;
    const auto fitted = Kriging::fit(X, y, o);
    EXPECT_EQ(fitted.nugget(), 0.0);
    expectInterpolates(fitted, X, y, "fit");
}

TEST(Kriging, ClosedFormLooMatchesRefitting) {
    const Eigen::MatrixXd X = randomPoints(12, 2, 11);
    const Eigen::VectorXd y = evaluate(X);
    const Eigen::Vector2d ls(0.35, 0.5);
    const double g = 1e-4;  // non-zero, so the nugget's place in the LOO variance is checked too
    for (auto k : {Kernel::Matern52, Kernel::SquaredExponential})
        for (auto t : {Trend::Constant, Trend::Linear}) {
            SCOPED_TRACE(toString(k) + "/" + toString(t));
            const auto full = Kriging::withHyperparameters(X, y, k, t, ls, g);
            const Eigen::VectorXd res = full.looResiduals();
            const Eigen::VectorXd var = full.looVariances();
            for (int i = 0; i < X.rows(); ++i) {
                const auto m = Kriging::withHyperparameters(withoutRow(X, i), withoutEntry(y, i), k, t, ls, g);
                const auto [mean, latentVar] = predictAt(m, X.row(i));
                EXPECT_NEAR(res[i], y[i] - mean, 1e-8 * (1.0 + std::abs(res[i]))) << "point " << i;
                // The closed form keeps the full fit's sigma^2 and is the variance of the residual,
                // i.e. the refitted latent variance plus the nugget, rescaled to the full sigma^2.
                const double expected = full.processVariance() * (latentVar / m.processVariance() + g);
                EXPECT_NEAR(var[i], expected, 1e-8 * expected) << "point " << i;
            }
        }
}

TEST(Kriging, FitPredictsSmoothFunctionDeterministically) {
    const Eigen::MatrixXd X = randomPoints(30, 2, 3);
    const Eigen::VectorXd y = evaluate(X);
    const Eigen::MatrixXd Xtest = randomPoints(200, 2, 99);
    const Eigen::VectorXd ytest = evaluate(Xtest);
    const double range = ytest.maxCoeff() - ytest.minCoeff();

    for (const std::string objective : {"likelihood", "loo"}) {
        SCOPED_TRACE(objective);
        KrigingOptions o;
        o.objective = objective;
        const auto m = Kriging::fit(X, y, o);
        double sse = 0;
        for (int i = 0; i < Xtest.rows(); ++i) sse += std::pow(predictAt(m, Xtest.row(i)).first - ytest[i], 2);
        EXPECT_LT(std::sqrt(sse / static_cast<double>(Xtest.rows())), 0.05 * range);

        // Start 0 of the search is the geometric midpoint of the bounds.
        const auto start = Kriging::withHyperparameters(X, y, o.kernel, o.trend,
                                                        Eigen::Vector2d::Constant(std::sqrt(o.lengthMin * o.lengthMax)),
                                                        std::sqrt(o.nuggetMin * o.nuggetMax));
        if (objective == "likelihood") {
            EXPECT_GE(m.logLikelihood(), start.logLikelihood());
        } else {
            EXPECT_LE(m.looResiduals().squaredNorm(), start.looResiduals().squaredNorm());
        }

        const auto again = Kriging::fit(X, y, o);
        EXPECT_EQ(again.lengthScales(), m.lengthScales());
        EXPECT_EQ(again.nugget(), m.nugget());
        EXPECT_EQ(predictAt(again, Xtest.row(0)), predictAt(m, Xtest.row(0)));
    }
}

TEST(Kriging, WarnsWhenLengthScaleOnBound) {
    // y ignores input 2, so its length scale runs to the upper bound.
    const Eigen::MatrixXd X = randomPoints(30, 3, 5);
    const Eigen::VectorXd y = evaluate(X);
    KrigingOptions o;
    o.starts = 10;
    const auto m = Kriging::fit(X, y, o);
    EXPECT_NEAR(m.lengthScales()[2], o.lengthMax, 0.1 * o.lengthMax);
    bool found = false;
    for (const auto& w : m.warnings()) {
        if (w.find("length scale 2") != std::string::npos && w.find("upper bound") != std::string::npos) found = true;
        EXPECT_EQ(w.find("length scale 0"), std::string::npos) << w;
        EXPECT_EQ(w.find("length scale 1"), std::string::npos) << w;
    }
    EXPECT_TRUE(found) << "warnings: " << nlohmann::json(m.warnings()).dump();

    const auto fixed = Kriging::withHyperparameters(X, y, o.kernel, o.trend, m.lengthScales(), m.nugget());
    EXPECT_TRUE(fixed.warnings().empty());
}

TEST(Kriging, JsonRoundTripIsBitIdentical) {
    const Eigen::MatrixXd X = randomPoints(25, 3, 21);
    Eigen::VectorXd y = evaluate(X);
    y += 0.3 * X.col(2);
    KrigingOptions o;
    o.trend = Trend::Linear;
    o.kernel = Kernel::SquaredExponential;
    o.starts = 5;
    const auto m = Kriging::fit(X, y, o);
    const std::string text = m.toJson().dump();
    const auto back = Kriging::fromJson(nlohmann::json::parse(text));

    EXPECT_EQ(back.kernel(), m.kernel());
    EXPECT_EQ(back.trend(), m.trend());
    EXPECT_EQ(back.lengthScales(), m.lengthScales());
    EXPECT_EQ(back.nugget(), m.nugget());
    EXPECT_EQ(back.processVariance(), m.processVariance());
    EXPECT_EQ(back.logLikelihood(), m.logLikelihood());
    EXPECT_EQ(back.warnings(), m.warnings());
    EXPECT_EQ(back.looResiduals(), m.looResiduals());
    auto wa = m.makeWorkspace();
    auto wb = back.makeWorkspace();
    const Eigen::MatrixXd P = randomPoints(100, 3, 1234) * 1.4 - Eigen::MatrixXd::Constant(100, 3, 0.2);
    for (int i = 0; i < P.rows(); ++i) {
        const Eigen::Vector3d x = P.row(i).transpose();
        double ma, va, mb, vb;
        m.predict(x.data(), wa, ma, va);
        back.predict(x.data(), wb, mb, vb);
        EXPECT_EQ(ma, mb);
        EXPECT_EQ(va, vb);
        EXPECT_EQ(m.predictMean(x.data(), wa), back.predictMean(x.data(), wb));
    }
    EXPECT_EQ(back.toJson().dump(), text);
}

TEST(Kriging, FromJsonNamesMissingOrBadField) {
    const Eigen::MatrixXd X = randomPoints(10, 2, 4);
    const auto m = Kriging::withHyperparameters(X, evaluate(X), Kernel::Matern52, Trend::Constant,
                                                Eigen::Vector2d(0.3, 0.3), 1e-8);
    const auto expectError = [](const nlohmann::json& j, const std::string& field) {
        try {
            Kriging::fromJson(j);
            ADD_FAILURE() << "no exception for " << field;
        } catch (const std::runtime_error& e) {
            EXPECT_NE(std::string(e.what()).find("'" + field + "'"), std::string::npos) << e.what();
        }
    };
    for (const std::string f : {"alpha", "cholesky", "lengthScales", "kernel", "X", "warnings"}) {
        auto j = m.toJson();
        j.erase(f);
        expectError(j, f);
    }
    auto j = m.toJson();
    j["beta"].push_back(1.0);
    expectError(j, "beta");
    j = m.toJson();
    j["trend"] = "cubic";
    expectError(j, "trend");
    j = m.toJson();
    j["cholesky"][3].push_back(0.0);
    expectError(j, "cholesky");
}

TEST(Kriging, PredictDoesNotAllocate) {
    const Eigen::MatrixXd X = randomPoints(30, 3, 8);
    const auto m = Kriging::withHyperparameters(X, evaluate(X), Kernel::Matern52, Trend::Linear,
                                                Eigen::Vector3d(0.3, 0.4, 1.0), 1e-6);
    auto ws = m.makeWorkspace();
    const Eigen::MatrixXd P = randomPoints(1000, 3, 77);

    // The hook is live: a vector allocates.
    mixload::testing::startCountingAllocations();
    { std::vector<double> probe(10); }
    ASSERT_GT(mixload::testing::stopCountingAllocations(), 0);

    double sum = 0;
    mixload::testing::startCountingAllocations();
    for (int i = 0; i < P.rows(); ++i) {
        double mean, var;
        const double x[3] = {P(i, 0), P(i, 1), P(i, 2)};
        m.predict(x, ws, mean, var);
        sum += mean + var + m.predictMean(x, ws);
    }
    EXPECT_EQ(mixload::testing::stopCountingAllocations(), 0);
    EXPECT_TRUE(std::isfinite(sum));
}

// Timing, not a check: run with --gtest_also_run_disabled_tests.
TEST(Kriging, DISABLED_Timing) {
    const Eigen::MatrixXd X = randomPoints(40, 7, 13);
    Eigen::VectorXd y(40);
    for (int i = 0; i < 40; ++i) {
        const auto x = X.row(i);
        y[i] = std::sin(3 * x[0]) + x[1] * x[1] + 0.5 * x[2] * x[3] + std::exp(-x[4]) + 0.2 * x[5];
    }
    KrigingOptions o;
    const auto t0 = std::chrono::steady_clock::now();
    const auto m = Kriging::fit(X, y, o);
    const auto t1 = std::chrono::steady_clock::now();
    std::printf("fit n=40 d=7 (%d starts): %.3f s\n", o.starts, std::chrono::duration<double>(t1 - t0).count());
    for (const auto& w : m.warnings()) std::printf("  warning: %s\n", w.c_str());

    auto ws = m.makeWorkspace();
    const Eigen::MatrixXd P = randomPoints(1000, 7, 5);
    const int calls = 1'000'000;
    double sum = 0;
    const auto t2 = std::chrono::steady_clock::now();
    for (int i = 0; i < calls; ++i) {
        double x[7];
        for (int k = 0; k < 7; ++k) x[k] = P(i % 1000, k);
        double mean, var;
        m.predict(x, ws, mean, var);
        sum += mean + var;
    }
    const auto t3 = std::chrono::steady_clock::now();
    for (int i = 0; i < calls; ++i) {
        double x[7];
        for (int k = 0; k < 7; ++k) x[k] = P(i % 1000, k);
        sum += m.predictMean(x, ws);
    }
    const auto t4 = std::chrono::steady_clock::now();
    std::printf("predict: %.3f us/call, predictMean: %.3f us/call (checksum %g)\n",
                std::chrono::duration<double, std::micro>(t3 - t2).count() / calls,
                std::chrono::duration<double, std::micro>(t4 - t3).count() / calls, sum);
}

// The covariance of two predictions is the posterior covariance under a flat prior on the trend:
// computed here the long way, by conditioning the joint Gaussian of the training data and the two
// points with a very wide prior on the trend coefficients.
TEST(Kriging, PairCovarianceIsTheFlatPriorPosterior) {
    const Eigen::MatrixXd X = randomPoints(12, 2, 21);
    const Eigen::VectorXd y = evaluate(X);
    const Eigen::Vector2d ls(0.3, 0.4);
    const double g = 1e-4;
    const auto matern = [&](const Eigen::RowVectorXd& a, const Eigen::RowVectorXd& b) {
        const double h = std::sqrt(5.0) * ((a - b).array() / ls.transpose().array()).matrix().norm();
        return (1 + h + h * h / 3) * std::exp(-h);
    };
    for (auto t : {Trend::Constant, Trend::Linear}) {
        SCOPED_TRACE(toString(t));
        const auto m = Kriging::withHyperparameters(X, y, Kernel::Matern52, t, ls, g);
        Eigen::MatrixXd P(2, 2);
        P << 0.31, 0.62, 0.36, 0.57;  // two nearby points
        const int n = 12, N = n + 2;
        Eigen::MatrixXd A(N, 2);
        A.topRows(n) = X;
        A.bottomRows(2) = P;
        const auto basis = [&](const Eigen::RowVectorXd& x) {
            Eigen::VectorXd f(t == Trend::Constant ? 1 : 3);
            f(0) = 1;
            if (t == Trend::Linear) f(1) = x(0), f(2) = x(1);
            return f;
        };
        const double wide = 1e7;
        Eigen::MatrixXd S(N, N);
        for (int i = 0; i < N; ++i)
            for (int j = 0; j < N; ++j)
                S(i, j) = matern(A.row(i), A.row(j)) + (i == j && i < n ? g : 0.0) + wide * basis(A.row(i)).dot(basis(A.row(j)));
        const Eigen::MatrixXd Stt = S.topLeftCorner(n, n), Stp = S.topRightCorner(n, 2);
        const Eigen::MatrixXd post = S.bottomRightCorner(2, 2) - Stp.transpose() * Stt.ldlt().solve(Stp);
        Eigen::Vector2d mean;
        Eigen::Matrix2d cov;
        const Eigen::VectorXd p1 = P.row(0).transpose(), p2 = P.row(1).transpose();
        m.predictPair(p1.data(), p2.data(), mean, cov);
        const Eigen::Matrix2d expected = m.processVariance() * post;
        for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) EXPECT_NEAR(cov(i, j), expected(i, j), 1e-4 * expected(0, 0)) << i << "," << j;
        // The diagonal and the means are predict()'s.
        const auto [m1, v1] = predictAt(m, P.row(0));
        const auto [m2, v2] = predictAt(m, P.row(1));
        EXPECT_NEAR(mean(0), m1, 1e-12);
        EXPECT_NEAR(mean(1), m2, 1e-12);
        EXPECT_NEAR(cov(0, 0), v1, 1e-12 * m.processVariance());
        EXPECT_NEAR(cov(1, 1), v2, 1e-12 * m.processVariance());
        // Nearby points share most of their error.
        EXPECT_GT(cov(0, 1) / std::sqrt(cov(0, 0) * cov(1, 1)), 0.5);
    }
}

// A smooth function fitted exactly puts the nugget on its lower bound; with a noise floor the
// nugget's variance is raised to it, and the model says so.
TEST(Kriging, NuggetIsKeptAtTheNoiseFloor) {
    const Eigen::MatrixXd X = randomPoints(20, 2, 31);
    const Eigen::VectorXd y = evaluate(X);
    KrigingOptions o;
    o.starts = 5;
    const auto free = Kriging::fit(X, y, o);
    const double floor = 1e-3;
    ASSERT_LT(free.processVariance() * free.nugget(), floor);
    o.noiseVarianceMin = floor;
    const auto m = Kriging::fit(X, y, o);
    EXPECT_GE(m.processVariance() * m.nugget(), 0.99 * floor);
    const auto w = m.warnings();
    EXPECT_TRUE(std::any_of(w.begin(), w.end(), [](const std::string& s) { return s.find("noise floor") != std::string::npos; }));
    // Above the floor already: nothing changes.
    o.noiseVarianceMin = 1e-3 * free.processVariance() * free.nugget();
    EXPECT_EQ(Kriging::fit(X, y, o).nugget(), free.nugget());
}

// A trend in some inputs only: the GLS slopes recover a law that is linear in those inputs, the
// process takes the small rest, and outside the data the prediction follows the law. The choice survives a round trip; a trend input that
// is not a column, or one given with a constant trend, is refused.
TEST(Kriging, TrendInSomeInputsRecoversTheirLaw) {
    const Eigen::MatrixXd X = randomPoints(30, 3, 11);
    Eigen::VectorXd y(30);
    const auto law = [](double x0, double x1, double x2) { return 1.0 - 2.0 * x0 + 4.0 * x2 + 0.05 * std::sin(3.0 * x1); };
    for (int i = 0; i < 30; ++i) y[i] = law(X(i, 0), X(i, 1), X(i, 2));
    KrigingOptions o;
    o.trend = Trend::Linear;
    o.trendInputs = {0, 2};
    const auto m = Kriging::fit(X, y, o);
    ASSERT_EQ(m.beta().size(), 3);
    EXPECT_NEAR(m.beta()[1], -2.0, 0.05);
    EXPECT_NEAR(m.beta()[2], 4.0, 0.05);
    auto ws = m.makeWorkspace();
    const double far[3] = {2.5, 0.5, 0.5};  // x0 1.5 beyond the data
    EXPECT_NEAR(m.predictMean(far, ws), law(2.5, 0.5, 0.5), 0.1);

    const auto back = Kriging::fromJson(nlohmann::json::parse(m.toJson().dump()));
    EXPECT_EQ(back.trendInputs(), m.trendInputs());
    auto bws = back.makeWorkspace();
    EXPECT_EQ(back.predictMean(far, bws), m.predictMean(far, ws));

    o.trendInputs = {0, 3};
    EXPECT_THROW(Kriging::fit(X, y, o), std::invalid_argument);
    o.trendInputs = {0};
    o.trend = Trend::Constant;
    EXPECT_THROW(Kriging::fit(X, y, o), std::invalid_argument);
}
