// SPDX-License-Identifier: GPL-3.0-or-later
#include "rsm/rsm.hpp"

#include <gsl/gsl_multifit.h>

#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

namespace mixload::surrogates {

namespace {

Eigen::MatrixXd design(const Eigen::MatrixXd& Z, const std::vector<Term>& terms) {
    Eigen::MatrixXd X(Z.rows(), static_cast<Eigen::Index>(terms.size()));
    Eigen::VectorXd z(Z.cols());
    for (Eigen::Index r = 0; r < Z.rows(); ++r) {
        z = Z.row(r).transpose();
        for (size_t t = 0; t < terms.size(); ++t) X(r, static_cast<Eigen::Index>(t)) = terms[t].eval(z.data());
    }
    return X;
}

struct LooFit {
    Eigen::MatrixXd xtxInv;
    Eigen::VectorXd loo, leverage;
    double press = std::numeric_limits<double>::infinity();
};

// Leave-one-out residuals e_i / (1 - h_ii) from the hat matrix: no refitting needed.
LooFit looOf(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, const Eigen::VectorXd& coef) {
    LooFit f;
    const Eigen::MatrixXd xtx = X.transpose() * X;
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(xtx);
    f.xtxInv = ldlt.solve(Eigen::MatrixXd::Identity(X.cols(), X.cols()));
    const Eigen::VectorXd e = y - X * coef;
    f.loo.resize(X.rows());
    f.leverage.resize(X.rows());
    double press = 0;
    for (Eigen::Index i = 0; i < X.rows(); ++i) {
        const double h = X.row(i) * f.xtxInv * X.row(i).transpose();
        f.leverage(i) = h;
        if (h > 1 - 1e-10) return f;  // a point the model cannot predict without: PRESS infinite
        f.loo(i) = e(i) / (1 - h);
        press += f.loo(i) * f.loo(i);
    }
    f.press = press;
    return f;
}

double pressOf(const Eigen::MatrixXd& Z, const Eigen::VectorXd& y, const std::vector<Term>& terms) {
    const Eigen::MatrixXd X = design(Z, terms);
    const Eigen::VectorXd coef = X.colPivHouseholderQr().solve(y);
    return looOf(X, y, coef).press;
}

}  // namespace

std::string Term::name(const std::vector<std::string>& in) const {
    if (i < 0) return "1";
    if (j < 0) return in.at(i);
    if (i == j) return in.at(i) + "^2";
    return in.at(i) + "*" + in.at(j);
}

std::vector<Term> fullQuadratic(int d) {
    std::vector<Term> t{{-1, -1}};
    for (int i = 0; i < d; ++i) t.push_back({i, -1});
    for (int i = 0; i < d; ++i) t.push_back({i, i});
    for (int i = 0; i < d; ++i)
        for (int j = i + 1; j < d; ++j) t.push_back({i, j});
    return t;
}

ResponseSurface ResponseSurface::fitTerms(const Eigen::MatrixXd& Z, const Eigen::VectorXd& y,
                                          const std::vector<Term>& terms) {
    const auto n = static_cast<size_t>(Z.rows()), p = terms.size();
    if (n < p)
        throw std::invalid_argument("response surface: " + std::to_string(p) + " terms need at least as many runs, have " +
                                    std::to_string(n));
    const Eigen::MatrixXd X = design(Z, terms);
    // GSL's least squares (SVD based) gives the coefficients and their covariance s^2 (X^T X)^-1.
    std::unique_ptr<gsl_matrix, void (*)(gsl_matrix*)> gx(gsl_matrix_alloc(n, p), gsl_matrix_free),
        cov(gsl_matrix_alloc(p, p), gsl_matrix_free);
    std::unique_ptr<gsl_vector, void (*)(gsl_vector*)> gy(gsl_vector_alloc(n), gsl_vector_free),
        c(gsl_vector_alloc(p), gsl_vector_free);
    std::unique_ptr<gsl_multifit_linear_workspace, void (*)(gsl_multifit_linear_workspace*)> work(
        gsl_multifit_linear_alloc(n, p), gsl_multifit_linear_free);
    for (size_t r = 0; r < n; ++r) {
        gsl_vector_set(gy.get(), r, y(static_cast<Eigen::Index>(r)));
        for (size_t k = 0; k < p; ++k)
            gsl_matrix_set(gx.get(), r, k, X(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(k)));
    }
    double chisq = 0;
    if (gsl_multifit_linear(gx.get(), gy.get(), c.get(), cov.get(), &chisq, work.get()) != 0)
        throw std::runtime_error("response surface: GSL least squares failed");
    ResponseSurface s;
    s.dims_ = static_cast<int>(Z.cols());
    s.terms_ = terms;
    s.coef_.resize(static_cast<Eigen::Index>(p));
    for (size_t k = 0; k < p; ++k) s.coef_(static_cast<Eigen::Index>(k)) = gsl_vector_get(c.get(), k);
    s.dof_ = static_cast<int>(n - p);
    s.s2_ = s.dof_ > 0 ? chisq / s.dof_ : 0.0;
    const auto loo = looOf(X, y, s.coef_);
    s.xtxInv_ = loo.xtxInv;
    s.loo_ = loo.loo;
    s.leverage_ = loo.leverage;
    s.press_ = loo.press;
    return s;
}

ResponseSurface ResponseSurface::fit(const Eigen::MatrixXd& Z, const Eigen::VectorXd& y, bool select) {
    const int d = static_cast<int>(Z.cols());
    const auto all = fullQuadratic(d);
    if (!select) return fitTerms(Z, y, all);
    std::vector<Term> chosen{all[0]};
    std::vector<Term> left(all.begin() + 1, all.end());
    double best = pressOf(Z, y, chosen);
    while (!left.empty() && static_cast<Eigen::Index>(chosen.size()) + 1 <= Z.rows() - 2) {
        size_t pick = left.size();
        double pickPress = best;
        for (size_t k = 0; k < left.size(); ++k) {
            auto trial = chosen;
            trial.push_back(left[k]);
            const double pr = pressOf(Z, y, trial);
            if (pr < pickPress) pickPress = pr, pick = k;
        }
        // Stop when the best addition does not lower PRESS by a meaningful amount (round-off
        // improvements on an exact fit would otherwise fill the model).
        if (pick == left.size() || pickPress > best * (1 - 1e-9)) break;
        chosen.push_back(left[pick]);
        left.erase(left.begin() + static_cast<long>(pick));
        best = pickPress;
        if (best <= 1e-24 * y.squaredNorm()) break;  // exact to round-off
    }
    return fitTerms(Z, y, chosen);
}

ResponseSurface::Loo ResponseSurface::selectedLoo(const Eigen::MatrixXd& Z, const Eigen::VectorXd& y) {
    const Eigen::Index n = Z.rows();
    Loo out{Eigen::VectorXd(n), Eigen::VectorXd(n)};
    std::vector<double> scratch;
    for (Eigen::Index i = 0; i < n; ++i) {
        Eigen::MatrixXd Zi(n - 1, Z.cols());
        Eigen::VectorXd yi(n - 1);
        for (Eigen::Index r = 0, k = 0; r < n; ++r)
            if (r != i) Zi.row(k) = Z.row(r), yi(k++) = y(r);
        const auto s = fit(Zi, yi, true);
        scratch.assign(s.terms().size(), 0.0);
        const Eigen::VectorXd z = Z.row(i).transpose();  // a row of a column-major matrix is strided
        double mean = 0, var = 0;
        s.predict(z.data(), scratch.data(), mean, var);
        out.residuals(i) = y(i) - mean;
        out.variances(i) = var;  // selection keeps n - p >= 2, so s^2 is defined
    }
    return out;
}

Eigen::VectorXd ResponseSurface::standardErrors() const {
    return (s2_ * xtxInv_.diagonal()).cwiseMax(0.0).cwiseSqrt();
}

double ResponseSurface::predict(const double* z) const {
    double m = 0;
    for (size_t t = 0; t < terms_.size(); ++t) m += coef_(static_cast<Eigen::Index>(t)) * terms_[t].eval(z);
    return m;
}

void ResponseSurface::predict(const double* z, double* f, double& mean, double& variance) const {
    const auto p = static_cast<Eigen::Index>(terms_.size());
    mean = 0;
    for (Eigen::Index t = 0; t < p; ++t) {
        f[t] = terms_[static_cast<size_t>(t)].eval(z);
        mean += coef_(t) * f[t];
    }
    double q = 0;
    for (Eigen::Index a = 0; a < p; ++a) {
        double row = 0;
        for (Eigen::Index b = 0; b < p; ++b) row += xtxInv_(a, b) * f[b];
        q += f[a] * row;
    }
    variance = s2_ * (1 + q);
}

void ResponseSurface::predictPair(const double* z1, const double* z2, Eigen::Vector2d& mean, Eigen::Matrix2d& cov) const {
    const auto p = static_cast<Eigen::Index>(terms_.size());
    Eigen::MatrixXd F(p, 2);
    for (Eigen::Index t = 0; t < p; ++t) {
        F(t, 0) = terms_[static_cast<size_t>(t)].eval(z1);
        F(t, 1) = terms_[static_cast<size_t>(t)].eval(z2);
    }
    mean = F.transpose() * coef_;
    cov = s2_ * (F.transpose() * xtxInv_ * F);
}

nlohmann::json ResponseSurface::toJson() const {
    nlohmann::json terms = nlohmann::json::array();
    for (const auto& t : terms_) terms.push_back({t.i, t.j});
    std::vector<double> inv(xtxInv_.data(), xtxInv_.data() + xtxInv_.size());
    return {{"dims", dims_},
            {"terms", terms},
            {"coefficients", std::vector<double>(coef_.data(), coef_.data() + coef_.size())},
            {"standard_errors", [&] {
                 const auto se = standardErrors();
                 return std::vector<double>(se.data(), se.data() + se.size());
             }()},
            {"xtx_inverse", inv},
            {"residual_variance", s2_},
            {"dof", dof_},
            {"press", press_},
            {"loo_residuals", std::vector<double>(loo_.data(), loo_.data() + loo_.size())}};
}

ResponseSurface ResponseSurface::fromJson(const nlohmann::json& j) {
    for (const char* k : {"dims", "terms", "coefficients", "xtx_inverse", "residual_variance", "dof", "press",
                          "loo_residuals"})
        if (!j.contains(k)) throw std::runtime_error(std::string("response surface: missing field '") + k + "'");
    ResponseSurface s;
    s.dims_ = j["dims"];
    for (const auto& t : j["terms"]) s.terms_.push_back({t.at(0).get<int>(), t.at(1).get<int>()});
    const auto c = j["coefficients"].get<std::vector<double>>();
    const auto inv = j["xtx_inverse"].get<std::vector<double>>();
    const auto loo = j["loo_residuals"].get<std::vector<double>>();
    const auto p = static_cast<Eigen::Index>(s.terms_.size());
    if (static_cast<Eigen::Index>(c.size()) != p || static_cast<Eigen::Index>(inv.size()) != p * p)
        throw std::runtime_error("response surface: coefficients do not match the terms");
    for (const auto& t : s.terms_)
        if (t.i >= s.dims_ || t.j >= s.dims_ || (t.i < 0 && t.j >= 0))
            throw std::runtime_error("response surface: a term names an input outside dims");
    s.coef_ = Eigen::Map<const Eigen::VectorXd>(c.data(), p);
    s.xtxInv_ = Eigen::Map<const Eigen::MatrixXd>(inv.data(), p, p);
    s.loo_ = Eigen::Map<const Eigen::VectorXd>(loo.data(), static_cast<Eigen::Index>(loo.size()));
    s.s2_ = j["residual_variance"];
    s.dof_ = j["dof"];
    s.press_ = j["press"];
    return s;
}

}  // namespace mixload::surrogates
