// SPDX-License-Identifier: GPL-3.0-or-later
#include "kriging/kriging.hpp"

#include <nlopt.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <sstream>
#include <stdexcept>

namespace mixload::surrogates {

std::string toString(Kernel k) {
    switch (k) {
        case Kernel::Matern52: return "matern52";
        case Kernel::SquaredExponential: return "squared-exponential";
    }
    throw std::invalid_argument("unknown kernel");
}

std::string toString(Trend t) {
    switch (t) {
        case Trend::Constant: return "constant";
        case Trend::Linear: return "linear";
    }
    throw std::invalid_argument("unknown trend");
}

Kernel kernelFromString(const std::string& s) {
    if (s == "matern52") return Kernel::Matern52;
    if (s == "squared-exponential") return Kernel::SquaredExponential;
    throw std::invalid_argument("unknown kernel '" + s + "' (allowed: matern52, squared-exponential)");
}

Trend trendFromString(const std::string& s) {
    if (s == "constant") return Trend::Constant;
    if (s == "linear") return Trend::Linear;
    throw std::invalid_argument("unknown trend '" + s + "' (allowed: constant, linear)");
}

namespace {

void validateData(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, Trend t, const std::vector<int>& trendInputs) {
    if (X.cols() < 1) throw std::invalid_argument("kriging: X has no columns");
    if (X.rows() != y.size())
        throw std::invalid_argument("kriging: X has " + std::to_string(X.rows()) + " rows but y has " +
                                    std::to_string(y.size()) + " values");
    for (size_t a = 0; a < trendInputs.size(); ++a) {
        if (trendInputs[a] < 0 || trendInputs[a] >= X.cols())
            throw std::invalid_argument("kriging: trend input " + std::to_string(trendInputs[a]) + " is not a column of X (0.." +
                                        std::to_string(X.cols() - 1) + ")");
        for (size_t b = 0; b < a; ++b)
            if (trendInputs[a] == trendInputs[b])
                throw std::invalid_argument("kriging: trend input " + std::to_string(trendInputs[a]) + " given twice");
    }
    if (!trendInputs.empty() && t != Trend::Linear)
        throw std::invalid_argument("kriging: trend inputs need a linear trend");
    const Eigen::Index p = trendCount(t, trendInputs, X.cols());
    // One more point than trend coefficients, or sigma^2 is zero by construction.
    if (X.rows() < p + 1)
        throw std::invalid_argument("kriging: " + std::to_string(X.rows()) + " points are too few for a " +
                                    toString(t) + " trend (need at least " + std::to_string(p + 1) + ")");
    if (!X.allFinite() || !y.allFinite()) throw std::invalid_argument("kriging: X or y has a non-finite value");
}

}  // namespace

void Kriging::setInverseLengths() {
    invLengths_ = lengthScales_.cwiseInverse();
    Xt_ = X_.transpose();
}

double Kriging::correlation(const double* a, const double* b) const {
    const int d = dims();
    const double* il = invLengths_.data();
    double h2 = 0.0;
    for (int k = 0; k < d; ++k) {
        const double t = (a[k] - b[k]) * il[k];
        h2 += t * t;
    }
    if (kernel_ == Kernel::SquaredExponential) return std::exp(-0.5 * h2);
    const double s = std::sqrt(5.0 * h2);
    return (1.0 + s + s * s / 3.0) * std::exp(-s);
}

void Kriging::trendBasis(const double* x, double* f) const {
    f[0] = 1.0;
    if (trend_ != Trend::Linear) return;
    if (trendInputs_.empty())
        for (int k = 0; k < dims(); ++k) f[k + 1] = x[k];
    else
        for (size_t k = 0; k < trendInputs_.size(); ++k) f[k + 1] = x[trendInputs_[k]];
}

bool Kriging::assemble() {
    const int n = size(), p = trendSize();
    setInverseLengths();

    Eigen::MatrixXd C(n, n);
    for (int j = 0; j < n; ++j) {
        C(j, j) = 1.0 + nugget_;
        for (int i = j + 1; i < n; ++i) C(i, j) = correlation(Xt_.col(i).data(), Xt_.col(j).data());
    }
    Eigen::LLT<Eigen::MatrixXd, Eigen::Lower> llt(C);
    if (llt.info() != Eigen::Success) return false;
    L_ = llt.matrixL();
    if (!L_.allFinite()) return false;

    Eigen::MatrixXd F(n, p);
    std::vector<double> f(static_cast<std::size_t>(p));
    for (int i = 0; i < n; ++i) {
        trendBasis(Xt_.col(i).data(), f.data());
        for (int c = 0; c < p; ++c) F(i, c) = f[static_cast<std::size_t>(c)];
    }
    const auto Lv = L_.triangularView<Eigen::Lower>();
    G_ = Lv.solve(F);
    const Eigen::VectorXd z = Lv.solve(y_);

    const Eigen::MatrixXd A = G_.transpose() * G_;
    Eigen::LLT<Eigen::MatrixXd> lltA(A);
    if (lltA.info() != Eigen::Success) return false;
    beta_ = lltA.solve(G_.transpose() * z);
    Ainv_ = lltA.solve(Eigen::MatrixXd::Identity(p, p));

    const Eigen::VectorXd e = z - G_ * beta_;
    // Floor keeps the log finite for an exactly-representable trend (e.g. constant y).
    sigma2_ = std::max(e.squaredNorm() / n, std::numeric_limits<double>::min());
    alpha_ = L_.transpose().triangularView<Eigen::Upper>().solve(e);

    const double logDet = 2.0 * L_.diagonal().array().log().sum();
    logLik_ = -0.5 * n * (std::log(2.0 * std::numbers::pi * sigma2_) + 1.0) - 0.5 * logDet;
    return std::isfinite(logLik_) && alpha_.allFinite() && Ainv_.allFinite();
}

Kriging Kriging::withHyperparameters(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, Kernel k, Trend t,
                                     const Eigen::VectorXd& lengthScales, double nugget,
                                     const std::vector<int>& trendInputs) {
    validateData(X, y, t, trendInputs);
    if (lengthScales.size() != X.cols())
        throw std::invalid_argument("kriging: " + std::to_string(lengthScales.size()) + " length scales for " +
                                    std::to_string(X.cols()) + " inputs");
    if (!(lengthScales.array() > 0.0).all() || !lengthScales.allFinite())
        throw std::invalid_argument("kriging: length scales must be positive and finite");
    if (!(nugget >= 0.0) || !std::isfinite(nugget))
        throw std::invalid_argument("kriging: nugget must be >= 0 and finite");
    Kriging m;
    m.kernel_ = k;
    m.trend_ = t;
    m.trendInputs_ = trendInputs;
    m.X_ = X;
    m.y_ = y;
    m.lengthScales_ = lengthScales;
    m.nugget_ = nugget;
    if (!m.assemble())
        throw std::runtime_error("kriging: correlation matrix is not numerically positive definite "
                                 "(increase the nugget or shorten the length scales)");
    return m;
}

Kriging::Workspace Kriging::makeWorkspace() const {
    const auto n = static_cast<std::size_t>(size()), p = static_cast<std::size_t>(trendSize());
    return Workspace{std::vector<double>(n), std::vector<double>(n), std::vector<double>(p),
                     std::vector<double>(p)};
}

void Kriging::checkWorkspace(const Workspace& ws) const {
    const auto n = static_cast<std::size_t>(size()), p = static_cast<std::size_t>(trendSize());
    if (ws.k.size() != n || ws.v.size() != n || ws.f.size() != p || ws.g.size() != p)
        throw std::invalid_argument("kriging: workspace was not made by this model's makeWorkspace()");
}

double Kriging::predictMean(const double* x, Workspace& ws) const {
    checkWorkspace(ws);
    const int n = size(), p = trendSize();
    double* f = ws.f.data();
    trendBasis(x, f);
    double mean = 0.0;
    for (int c = 0; c < p; ++c) mean += f[c] * beta_[c];
    const double* a = alpha_.data();
    const double* xt = Xt_.data();
    const int d = dims();
    for (int i = 0; i < n; ++i) mean += correlation(x, xt + static_cast<std::ptrdiff_t>(i) * d) * a[i];
    return mean;
}

void Kriging::predict(const double* x, Workspace& ws, double& mean, double& variance) const {
    checkWorkspace(ws);
    const int n = size(), p = trendSize();
    double* k = ws.k.data();
    double* v = ws.v.data();
    double* f = ws.f.data();
    double* u = ws.g.data();

    trendBasis(x, f);
    mean = 0.0;
    for (int c = 0; c < p; ++c) mean += f[c] * beta_[c];
    const double* a = alpha_.data();
    const double* xt = Xt_.data();
    const int d = dims();
    for (int i = 0; i < n; ++i) {
        k[i] = correlation(x, xt + static_cast<std::ptrdiff_t>(i) * d);
        mean += k[i] * a[i];
        v[i] = k[i];
    }

    // v = L^-1 k, column-oriented so the inner loop runs down a contiguous column of L.
    const double* Ld = L_.data();
    for (int j = 0; j < n; ++j) {
        const double* col = Ld + static_cast<std::ptrdiff_t>(j) * n;
        const double vj = v[j] / col[j];
        v[j] = vj;
        for (int i = j + 1; i < n; ++i) v[i] -= col[i] * vj;
    }
    double vv = 0.0;
    for (int i = 0; i < n; ++i) vv += v[i] * v[i];

    // u = F^T C^-1 k - f = G^T v - f.
    const double* Gd = G_.data();
    for (int c = 0; c < p; ++c) {
        const double* col = Gd + static_cast<std::ptrdiff_t>(c) * n;
        double s = 0.0;
        for (int i = 0; i < n; ++i) s += col[i] * v[i];
        u[c] = s - f[c];
    }
    double uAu = 0.0;
    for (int c = 0; c < p; ++c) {
        double s = 0.0;
        for (int r = 0; r < p; ++r) s += Ainv_(r, c) * u[r];
        uAu += s * u[c];
    }
    variance = std::max(0.0, sigma2_ * (1.0 - vv + uAu));
}

void Kriging::predictPair(const double* x1, const double* x2, Eigen::Vector2d& mean, Eigen::Matrix2d& cov) const {
    const int n = size(), p = trendSize(), d = dims();
    Eigen::MatrixXd K(n, 2), F(p, 2);
    const double* xs[2] = {x1, x2};
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < n; ++i) K(i, j) = correlation(xs[j], Xt_.data() + static_cast<std::ptrdiff_t>(i) * d);
        trendBasis(xs[j], F.col(j).data());
        mean(j) = F.col(j).dot(beta_) + K.col(j).dot(alpha_);
    }
    const Eigen::MatrixXd V = L_.triangularView<Eigen::Lower>().solve(K);  // L^-1 k
    const Eigen::MatrixXd U = G_.transpose() * V - F;                      // F^T C^-1 k - f
    Eigen::Matrix2d R;
    R(0, 0) = R(1, 1) = 1.0;
    R(0, 1) = R(1, 0) = correlation(x1, x2);
    cov = sigma2_ * (R - V.transpose() * V + U.transpose() * Ainv_ * U);
    cov(0, 0) = std::max(cov(0, 0), 0.0);
    cov(1, 1) = std::max(cov(1, 1), 0.0);
}

Eigen::VectorXd Kriging::looPrecisionDiagonal() const {
    const int n = size();
    const Eigen::MatrixXd Linv =
        L_.triangularView<Eigen::Lower>().solve(Eigen::MatrixXd::Identity(n, n));
    // C^-1 = Linv^T Linv, so its diagonal is the squared column norms of Linv.
    const Eigen::VectorXd cinvDiag = Linv.colwise().squaredNorm().transpose();
    const Eigen::MatrixXd H = Linv.transpose() * G_;  // C^-1 F
    return cinvDiag - (H * Ainv_).cwiseProduct(H).rowwise().sum();
}

Eigen::VectorXd Kriging::looResiduals() const {
    // Q y = C^-1 (y - F beta) = alpha because beta is the GLS estimate.
    return alpha_.cwiseQuotient(looPrecisionDiagonal());
}

Eigen::VectorXd Kriging::looVariances() const {
    return looPrecisionDiagonal().cwiseInverse() * sigma2_;
}

// ---- hyperparameter search -------------------------------------------------------------------

namespace {

struct SearchContext {
    const Eigen::MatrixXd* X = nullptr;
    const Eigen::VectorXd* y = nullptr;
    const KrigingOptions* o = nullptr;
    int d = 0;
    bool loo = false;
    double bestValue = std::numeric_limits<double>::infinity();
    std::vector<double> best;
};

// Worse than any objective a factorisable point gives, but finite so BOBYQA's quadratic model
// survives a failed trial.
constexpr double kFailedObjective = 1e30;

double evaluate(SearchContext& c, const double* theta) {
    Eigen::VectorXd ls(c.d);
    for (int k = 0; k < c.d; ++k) ls[k] = std::exp(theta[k]);
    const double g = c.o->estimateNugget ? std::exp(theta[c.d]) : c.o->nugget;
    Kriging m = Kriging::withHyperparameters(*c.X, *c.y, c.o->kernel, c.o->trend, ls, g, c.o->trendInputs);
    if (!c.loo) return -m.logLikelihood();
    const Eigen::VectorXd r = m.looResiduals();
    const double mse = r.squaredNorm() / static_cast<double>(r.size());
    return std::isfinite(mse) ? mse : kFailedObjective;
}

double objective(unsigned m, const double* theta, double* grad, void* data) {
    (void)grad;  // derivative-free algorithms only
    auto& c = *static_cast<SearchContext*>(data);
    double value;
    try {
        value = evaluate(c, theta);
    } catch (const std::runtime_error&) {
        value = kFailedObjective;
    }
    // Tracked here, not from nlopt's return, so the best point survives any stopping code.
    if (value < c.bestValue) {
        c.bestValue = value;
        c.best.assign(theta, theta + m);
    }
    return value;
}

// Uniform in (0,1) straight from mt19937's output, whose sequence the standard fixes; the
// standard distributions are implementation-defined and would make fits differ between libraries.
double uniform01(std::mt19937& gen) { return (static_cast<double>(gen()) + 0.5) / 4294967296.0; }

// Start 0 at the centre of the (log) box, the rest a Latin hypercube.
std::vector<std::vector<double>> startPoints(const std::vector<double>& lb, const std::vector<double>& ub,
                                             int starts, unsigned seed) {
    const std::size_t m = lb.size();
    std::vector<std::vector<double>> pts(static_cast<std::size_t>(starts), std::vector<double>(m));
    for (std::size_t k = 0; k < m; ++k) pts[0][k] = 0.5 * (lb[k] + ub[k]);
    const int s = starts - 1;
    if (s <= 0) return pts;
    std::mt19937 gen(seed);
    std::vector<int> perm(static_cast<std::size_t>(s));
    for (std::size_t k = 0; k < m; ++k) {
        for (int i = 0; i < s; ++i) perm[static_cast<std::size_t>(i)] = i;
        for (int i = s - 1; i > 0; --i)
            std::swap(perm[static_cast<std::size_t>(i)], perm[gen() % static_cast<unsigned>(i + 1)]);
        for (int i = 0; i < s; ++i) {
            const double u = (perm[static_cast<std::size_t>(i)] + uniform01(gen)) / s;
            pts[static_cast<std::size_t>(i + 1)][k] = lb[k] + u * (ub[k] - lb[k]);
        }
    }
    return pts;
}

void validateOptions(const KrigingOptions& o) {
    if (o.starts < 1) throw std::invalid_argument("kriging: starts must be >= 1");
    if (!(o.lengthMin > 0.0 && o.lengthMin < o.lengthMax && std::isfinite(o.lengthMax)))
        throw std::invalid_argument("kriging: need 0 < lengthMin < lengthMax");
    if (o.estimateNugget && !(o.nuggetMin > 0.0 && o.nuggetMin < o.nuggetMax && std::isfinite(o.nuggetMax)))
        throw std::invalid_argument("kriging: need 0 < nuggetMin < nuggetMax");
    if (!o.estimateNugget && !(o.nugget >= 0.0 && std::isfinite(o.nugget)))
        throw std::invalid_argument("kriging: nugget must be >= 0 and finite");
    if (o.objective != "likelihood" && o.objective != "loo")
        throw std::invalid_argument("kriging: unknown objective '" + o.objective + "' (allowed: likelihood, loo)");
}

std::string formatBound(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

}  // namespace

Kriging Kriging::fit(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, const KrigingOptions& o) {
    validateData(X, y, o.trend, o.trendInputs);
    validateOptions(o);
    const int d = static_cast<int>(X.cols());
    const int m = d + (o.estimateNugget ? 1 : 0);

    std::vector<double> lb(static_cast<std::size_t>(m), std::log(o.lengthMin));
    std::vector<double> ub(static_cast<std::size_t>(m), std::log(o.lengthMax));
    if (o.estimateNugget) {
        lb.back() = std::log(o.nuggetMin);
        ub.back() = std::log(o.nuggetMax);
    }

    SearchContext ctx;
    ctx.X = &X;
    ctx.y = &y;
    ctx.o = &o;
    ctx.d = d;
    ctx.loo = o.objective == "loo";
    // BOBYQA builds a quadratic model and needs at least two variables.
    const nlopt_algorithm alg = m >= 2 ? NLOPT_LN_BOBYQA : NLOPT_LN_SBPLX;
    for (auto x0 : startPoints(lb, ub, o.starts, o.seed)) {
        std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(nlopt_create(alg, static_cast<unsigned>(m)),
                                                                    &nlopt_destroy);
        if (!opt) throw std::runtime_error("kriging: nlopt_create failed");
        nlopt_set_lower_bounds(opt.get(), lb.data());
        nlopt_set_upper_bounds(opt.get(), ub.data());
        nlopt_set_min_objective(opt.get(), &objective, &ctx);
        nlopt_set_xtol_abs1(opt.get(), 1e-4);  // in log units: 0.01 % of a length scale
        nlopt_set_ftol_abs(opt.get(), 1e-9);
        nlopt_set_maxeval(opt.get(), 100 * (m + 1));
        double f = 0.0;
        nlopt_optimize(opt.get(), x0.data(), &f);  // result code ignored: the context keeps the best point
    }
    if (!(ctx.bestValue < kFailedObjective))
        throw std::runtime_error("kriging: no hyperparameters in the search box give a positive definite "
                                 "correlation matrix (estimate the nugget or raise it)");

    Eigen::VectorXd ls(d);
    for (int k = 0; k < d; ++k) ls[k] = std::exp(ctx.best[static_cast<std::size_t>(k)]);
    const double g = o.estimateNugget ? std::exp(ctx.best.back()) : o.nugget;
    Kriging model = withHyperparameters(X, y, o.kernel, o.trend, ls, g, o.trendInputs);
    if (o.noiseVarianceMin > 0 && model.sigma2_ * model.nugget_ < o.noiseVarianceMin) {
        // sigma^2 is profiled, so fixing g = floor / sigma^2 moves sigma^2: a few fixed-point steps.
        KrigingOptions fixed = o;
        fixed.estimateNugget = false;
        fixed.noiseVarianceMin = 0;
        for (int it = 0; it < 8 && model.sigma2_ * model.nugget_ < 0.99 * o.noiseVarianceMin; ++it) {
            fixed.nugget = std::min(o.noiseVarianceMin / model.sigma2_, o.nuggetMax);
            model = fit(X, y, fixed);
        }
        model.warnings_.push_back("nugget raised to the data's noise floor: sigma^2 g = " + formatBound(model.sigma2_ * model.nugget_) +
                                  " (floor " + formatBound(o.noiseVarianceMin) + ")");
        return model;
    }

    // "On a bound" within 1 % of the log-width of the box: the optimiser stalls a little short of a
    // bound where the objective is flat, which is exactly the case worth reporting.
    const auto near = [](double v, double bound, double lo, double hi) {
        return std::abs(std::log(v) - std::log(bound)) <= 0.01 * std::log(hi / lo);
    };
    for (int k = 0; k < d; ++k) {
        const std::string name = "length scale " + std::to_string(k);
        if (near(ls[k], o.lengthMax, o.lengthMin, o.lengthMax))
            model.warnings_.push_back(name + " sits on its upper bound " + formatBound(o.lengthMax) +
                                      " (input " + std::to_string(k) + " has little effect)");
        else if (near(ls[k], o.lengthMin, o.lengthMin, o.lengthMax))
            model.warnings_.push_back(name + " sits on its lower bound " + formatBound(o.lengthMin) +
                                      " (response varies faster than the sampling of input " +
                                      std::to_string(k) + " resolves)");
    }
    if (o.estimateNugget) {
        if (near(g, o.nuggetMax, o.nuggetMin, o.nuggetMax))
            model.warnings_.push_back("nugget sits on its upper bound " + formatBound(o.nuggetMax) +
                                      " (data look noisy to this kernel; the model smooths rather than interpolates)");
        else if (near(g, o.nuggetMin, o.nuggetMin, o.nuggetMax))
            model.warnings_.push_back("nugget sits on its lower bound " + formatBound(o.nuggetMin) +
                                      " (the model interpolates the data)");
    }
    return model;
}

// ---- JSON ------------------------------------------------------------------------------------

namespace {

constexpr const char* kFormat = "mixload-kriging";
constexpr int kVersion = 1;

nlohmann::json rows(const Eigen::MatrixXd& M) {
    auto a = nlohmann::json::array();
    for (Eigen::Index i = 0; i < M.rows(); ++i) {
        auto r = nlohmann::json::array();
        for (Eigen::Index c = 0; c < M.cols(); ++c) r.push_back(M(i, c));
        a.push_back(std::move(r));
    }
    return a;
}

nlohmann::json values(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }

[[noreturn]] void bad(const std::string& field, const std::string& why) {
    throw std::runtime_error("kriging JSON: field '" + field + "' " + why);
}

const nlohmann::json& field(const nlohmann::json& j, const std::string& name) {
    const auto it = j.find(name);
    if (it == j.end()) bad(name, "is missing");
    return *it;
}

double number(const nlohmann::json& j, const std::string& name) {
    const auto& v = field(j, name);
    if (!v.is_number()) bad(name, "must be a number");
    const double x = v.get<double>();
    if (!std::isfinite(x)) bad(name, "must be finite");
    return x;
}

int count(const nlohmann::json& j, const std::string& name) {
    const auto& v = field(j, name);
    if (!v.is_number_integer() || v.get<long long>() < 1 || v.get<long long>() > 1'000'000)
        bad(name, "must be a positive integer");
    return v.get<int>();
}

std::string text(const nlohmann::json& j, const std::string& name) {
    const auto& v = field(j, name);
    if (!v.is_string()) bad(name, "must be a string");
    return v.get<std::string>();
}

double element(const nlohmann::json& v, const std::string& name) {
    if (!v.is_number()) bad(name, "has a non-numeric element");
    const double x = v.get<double>();
    if (!std::isfinite(x)) bad(name, "has a non-finite element");
    return x;
}

Eigen::VectorXd vectorField(const nlohmann::json& j, const std::string& name, int size) {
    const auto& v = field(j, name);
    if (!v.is_array() || static_cast<int>(v.size()) != size)
        bad(name, "must be an array of " + std::to_string(size) + " numbers");
    Eigen::VectorXd out(size);
    for (int i = 0; i < size; ++i) out[i] = element(v[static_cast<std::size_t>(i)], name);
    return out;
}

// lowerOnly: row i holds only its first i + 1 entries (the Cholesky factor).
Eigen::MatrixXd matrixField(const nlohmann::json& j, const std::string& name, int nrows, int ncols,
                            bool lowerOnly = false) {
    const auto& v = field(j, name);
    if (!v.is_array() || static_cast<int>(v.size()) != nrows)
        bad(name, "must be an array of " + std::to_string(nrows) + " rows");
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(nrows, ncols);
    for (int i = 0; i < nrows; ++i) {
        const auto& r = v[static_cast<std::size_t>(i)];
        const int len = lowerOnly ? i + 1 : ncols;
        if (!r.is_array() || static_cast<int>(r.size()) != len)
            bad(name, "row " + std::to_string(i) + " must hold " + std::to_string(len) + " numbers");
        for (int c = 0; c < len; ++c) out(i, c) = element(r[static_cast<std::size_t>(c)], name);
    }
    return out;
}

}  // namespace

nlohmann::json Kriging::toJson() const {
    nlohmann::json j;
    j["format"] = kFormat;
    j["version"] = kVersion;
    j["kernel"] = toString(kernel_);
    j["trend"] = toString(trend_);
    if (!trendInputs_.empty()) j["trendInputs"] = trendInputs_;
    j["dims"] = dims();
    j["size"] = size();
    j["X"] = rows(X_);
    j["y"] = values(y_);
    j["lengthScales"] = values(lengthScales_);
    j["nugget"] = nugget_;
    j["processVariance"] = sigma2_;
    j["logLikelihood"] = logLik_;
    j["beta"] = values(beta_);
    j["alpha"] = values(alpha_);
    auto chol = nlohmann::json::array();
    for (int i = 0; i < size(); ++i) {
        auto r = nlohmann::json::array();
        for (int c = 0; c <= i; ++c) r.push_back(L_(i, c));
        chol.push_back(std::move(r));
    }
    j["cholesky"] = std::move(chol);
    j["trendFactor"] = rows(G_);
    j["trendPrecisionInverse"] = rows(Ainv_);
    j["warnings"] = warnings_;
    return j;
}

Kriging Kriging::fromJson(const nlohmann::json& j) {
    if (!j.is_object()) throw std::runtime_error("kriging JSON: expected an object");
    if (text(j, "format") != kFormat) bad("format", std::string("must be \"") + kFormat + "\"");
    if (!field(j, "version").is_number_integer() || field(j, "version").get<int>() != kVersion)
        bad("version", "must be " + std::to_string(kVersion));
    Kriging m;
    try {
        m.kernel_ = kernelFromString(text(j, "kernel"));
    } catch (const std::invalid_argument& e) {
        bad("kernel", e.what());
    }
    try {
        m.trend_ = trendFromString(text(j, "trend"));
    } catch (const std::invalid_argument& e) {
        bad("trend", e.what());
    }
    const int d = count(j, "dims"), n = count(j, "size");
    if (j.contains("trendInputs")) {
        if (!j["trendInputs"].is_array() || m.trend_ != Trend::Linear) bad("trendInputs", "must be a list of input columns, with a linear trend");
        for (const auto& v : j["trendInputs"]) {
            if (!v.is_number_integer() || v.get<int>() < 0 || v.get<int>() >= d) bad("trendInputs", "must name columns 0.." + std::to_string(d - 1));
            m.trendInputs_.push_back(v.get<int>());
        }
    }
    const int p = trendCount(m.trend_, m.trendInputs_, d);
    m.X_ = matrixField(j, "X", n, d);
    m.y_ = vectorField(j, "y", n);
    m.lengthScales_ = vectorField(j, "lengthScales", d);
    if (!(m.lengthScales_.array() > 0.0).all()) bad("lengthScales", "must be positive");
    m.nugget_ = number(j, "nugget");
    if (m.nugget_ < 0.0) bad("nugget", "must be >= 0");
    m.sigma2_ = number(j, "processVariance");
    if (m.sigma2_ <= 0.0) bad("processVariance", "must be positive");
    m.logLik_ = number(j, "logLikelihood");
    m.beta_ = vectorField(j, "beta", p);
    m.alpha_ = vectorField(j, "alpha", n);
    m.L_ = matrixField(j, "cholesky", n, n, true);
    if (!(m.L_.diagonal().array() > 0.0).all()) bad("cholesky", "must have a positive diagonal");
    m.G_ = matrixField(j, "trendFactor", n, p);
    m.Ainv_ = matrixField(j, "trendPrecisionInverse", p, p);
    const auto& w = field(j, "warnings");
    if (!w.is_array()) bad("warnings", "must be an array of strings");
    for (const auto& s : w) {
        if (!s.is_string()) bad("warnings", "must be an array of strings");
        m.warnings_.push_back(s.get<std::string>());
    }
    m.setInverseLengths();
    return m;
}

}  // namespace mixload::surrogates
