// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <Eigen/Dense>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace mixload::surrogates {

enum class Kernel { Matern52, SquaredExponential };
enum class Trend { Constant, Linear };
std::string toString(Kernel k);
std::string toString(Trend t);
// Throw std::invalid_argument on an unknown name.
Kernel kernelFromString(const std::string& s);
Trend trendFromString(const std::string& s);
// Coefficients of a trend over d inputs: 1, or 1 + the linear trend's inputs (all when none are named).
inline int trendCount(Trend t, const std::vector<int>& trendInputs, long d) {
    return t == Trend::Constant ? 1 : 1 + (trendInputs.empty() ? static_cast<int>(d) : static_cast<int>(trendInputs.size()));
}

struct KrigingOptions {
    Kernel kernel = Kernel::Matern52;
    Trend trend = Trend::Constant;
    // A linear trend's inputs (column numbers); empty: all of them. A trend in the inputs that
    // carry a known law (e.g. log feed and log speed) leaves the rest to the process, with fewer
    // coefficients for few runs to pin down.
    std::vector<int> trendInputs;
    bool estimateNugget = true;  // nugget (as a fraction of the process variance) estimated with the length scales
    double nugget = 1e-10;       // used when !estimateNugget (a tiny jitter keeps the Cholesky stable; 0 allowed)
    double nuggetMin = 1e-10, nuggetMax = 1e-1;
    double lengthMin = 0.02, lengthMax = 20.0;  // bounds of each length scale, in scaled input units
    // Start 0 is the geometric midpoint of the bounds (every length scale sqrt(lengthMin*lengthMax),
    // nugget sqrt(nuggetMin*nuggetMax)); the others are a Latin hypercube in log space drawn from seed.
    int starts = 20;
    unsigned seed = 1;
    std::string objective = "likelihood";  // or "loo": minimise the closed-form LOO mean squared error
    // The scatter the data are known to carry (variance, output units): a fitted nugget whose
    // variance sigma^2 g falls below it is raised to it (the length scales refitted with the
    // nugget fixed), since a model that treats noisy runs as exact gives intervals too narrow.
    double noiseVarianceMin = 0;
};

// Gaussian-process regression with a GLS-estimated trend (universal kriging).
// Covariance sigma^2 (R + g I); sigma^2 is profiled out with the maximum-likelihood divisor n (not
// n - p), so processVariance() is the value that maximises the concentrated likelihood.
class Kriging {
public:
    // X: n x d training inputs (already scaled by the caller, typically to [0,1]); y: n outputs.
    static Kriging fit(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, const KrigingOptions& o);
    // Hyperparameters fixed, no optimisation. Throws std::invalid_argument on bad sizes or values and
    // std::runtime_error when the correlation matrix is not numerically positive definite.
    static Kriging withHyperparameters(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, Kernel k,
                                       Trend t, const Eigen::VectorXd& lengthScales, double nugget,
                                       const std::vector<int>& trendInputs = {});

    int dims() const { return static_cast<int>(X_.cols()); }
    int size() const { return static_cast<int>(X_.rows()); }

    // Scratch space for predict; one per thread. k: correlations with the training points,
    // v: L^-1 k, f: trend basis at x, g: F^T C^-1 k - f.
    struct Workspace {
        std::vector<double> k, v, f, g;
    };
    Workspace makeWorkspace() const;
    // Allocation-free. x points to dims() doubles. variance is that of the latent mean (universal
    // kriging, including the trend-estimation term), clipped at >= 0; the nugget is not added.
    double predictMean(const double* x, Workspace& ws) const;
    void predict(const double* x, Workspace& ws, double& mean, double& variance) const;
    // Means of two points and the 2 x 2 covariance of their latent errors (the nugget not added):
    // the off-diagonal term is what a difference of two predictions needs, since nearby points
    // share most of their error. Allocates; the diagonal equals predict()'s variances.
    void predictPair(const double* x1, const double* x2, Eigen::Vector2d& mean, Eigen::Matrix2d& cov) const;

    // Closed-form leave-one-out with the hyperparameters (including sigma^2) of the full fit and the
    // trend re-estimated: residual_i = y_i - yhat_{-i} = (Q y)_i / Q_ii and variance_i = sigma^2 / Q_ii.
    // The variance is that of the residual, so it includes the nugget term sigma^2 g.
    Eigen::VectorXd looResiduals() const;
    Eigen::VectorXd looVariances() const;

    // Concentrated log-likelihood including its constants: -n/2 (log(2 pi sigma^2) + 1) - 1/2 log det(R + g I).
    double logLikelihood() const { return logLik_; }
    const Eigen::VectorXd& lengthScales() const { return lengthScales_; }
    double nugget() const { return nugget_; }
    double processVariance() const { return sigma2_; }
    Kernel kernel() const { return kernel_; }
    Trend trend() const { return trend_; }
    const std::vector<int>& trendInputs() const { return trendInputs_; }  // empty: all (linear)
    const Eigen::VectorXd& beta() const { return beta_; }

    // Hyperparameters that ended on a search bound (inputs numbered from 0). Only fit() knows the
    // bounds, so models from withHyperparameters() have none.
    std::vector<std::string> warnings() const { return warnings_; }

    // Stores everything the predictor uses, so predictions after a round trip are bit-identical.
    // fromJson throws std::runtime_error naming the missing or bad field.
    nlohmann::json toJson() const;
    static Kriging fromJson(const nlohmann::json& j);

private:
    Kriging() = default;
    // Computes the factorisation and everything derived from it from X_, y_, kernel_, trend_,
    // lengthScales_ and nugget_. False when a Cholesky factorisation fails.
    bool assemble();
    void setInverseLengths();
    void checkWorkspace(const Workspace& ws) const;  // sizes only: a foreign workspace would overrun
    int trendSize() const { return trendCount(trend_, trendInputs_, dims()); }
    double correlation(const double* a, const double* b) const;
    void trendBasis(const double* x, double* f) const;
    // Diagonal of Q = C^-1 - C^-1 F (F^T C^-1 F)^-1 F^T C^-1.
    Eigen::VectorXd looPrecisionDiagonal() const;

    Kernel kernel_ = Kernel::Matern52;
    Trend trend_ = Trend::Constant;
    std::vector<int> trendInputs_;
    Eigen::MatrixXd X_;   // n x d, as given
    Eigen::MatrixXd Xt_;  // d x n, so each training point is contiguous for the hot loop
    Eigen::VectorXd y_;
    Eigen::VectorXd lengthScales_, invLengths_;
    double nugget_ = 0.0;
    double sigma2_ = 0.0;
    double logLik_ = 0.0;
    Eigen::MatrixXd L_;     // lower Cholesky factor of C = R + g I
    Eigen::MatrixXd G_;     // L^-1 F (n x p)
    Eigen::MatrixXd Ainv_;  // (F^T C^-1 F)^-1 (p x p)
    Eigen::VectorXd beta_, alpha_;  // GLS trend coefficients; C^-1 (y - F beta)
    std::vector<std::string> warnings_;
};

}  // namespace mixload::surrogates
