// SPDX-License-Identifier: GPL-3.0-or-later
#include "model.hpp"

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_qrng.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <regex>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "common/stats.hpp"
#include "error_stats.hpp"
#include "regime.hpp"

namespace mixload::surrogates {

namespace {

constexpr const char* kSchema = "mixload-surrogate";
constexpr double kZ95 = 1.959963984540054;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

std::vector<Transform> candidates(const std::string& mode, bool similarity) {
    const auto in = modelInputs(similarity);
    Transform none, logs;
    none.similarity = logs.similarity = similarity;
    logs.logOutput = true;
    // Log of the dimensional inputs (scale parameters); the friction coefficients stay linear.
    for (size_t k = 0; k < in.size(); ++k) logs.logInput[k] = in[k].unit != "1";
    Transform outOnly = none, inOnly = logs;
    outOnly.logOutput = true;
    inOnly.logOutput = false;
    if (mode == "none") return {none};
    if (mode == "log") return {logs};
    if (mode == "auto") return {none, outOnly, inOnly, logs};
    throw InputError("transform", mode, "auto, none or log");
}

double fwd(bool log, double v) { return log ? std::log(v) : v; }
double back(bool log, double v) { return log ? std::exp(v) : v; }

}  // namespace

std::vector<ModelInput> modelInputs(bool similarity) {
    std::vector<ModelInput> out;
    if (!similarity) {
        for (int k = 0; k < kInputs; ++k) out.push_back({kInputSpecs[static_cast<size_t>(k)].name, kInputSpecs[static_cast<size_t>(k)].unit, k});
        return out;
    }
    return {{"mu_s", "1", 0}, {"mu_d", "1", 1}, {"d/i0", "m", 3, 2}, {"feed/rho", "m3/h", 5, 4}, {"rpm", "rpm", 6}};
}

std::string Transform::describe() const {
    std::string s = similarity ? (logOutput ? "log(M/rho)" : "M/rho") : (logOutput ? "log M" : "M");
    std::string in;
    const auto names = modelInputs(similarity);
    for (size_t k = 0; k < names.size(); ++k)
        if (logInput[k]) in += std::string(in.empty() ? "" : ", ") + names[k].name;
    std::string inputs = in.empty() ? " of linear inputs" : " of log(" + in + ")";
    if (similarity) inputs += " (similarity: mu_s, mu_d, d/i0, feed/rho, rpm)";
    return s + inputs;
}

void Surrogate::setInputs() { in_ = modelInputs(tf_.similarity); }

void Surrogate::derive(const Point& x, double* v) const {
    for (size_t j = 0; j < in_.size(); ++j) {
        const auto& m = in_[j];
        v[j] = m.den < 0 ? x[static_cast<size_t>(m.num)] : x[static_cast<size_t>(m.num)] / x[static_cast<size_t>(m.den)];
    }
}

void Surrogate::scale(const Point& x, double* z) const {
    derive(x, z);
    for (size_t k = 0; k < in_.size(); ++k) {
        const double u = fwd(tf_.logInput[k], z[k]);
        const double s = (u - umin_[k]) / (umax_[k] - umin_[k]);
        // Response surfaces live on [-1, 1] (orthogonal-ish terms), kriging on [0, 1].
        z[k] = kind_ == "rsm" ? 2 * s - 1 : s;
    }
}

std::vector<double> Surrogate::coordinates(const Point& x) const {
    double z[kInputs];
    scale(x, z);
    return {z, z + dims()};
}

namespace {
// A full barrel of the scene's powder as a volume [m3], from a model's provenance (0: unknown).
double fullBarrelIn(const nlohmann::json& provenance) {
    return provenance.is_object() ? provenance.value("full_barrel_m3", 0.0) : 0.0;
}

// The share of a quasi-random sample of the training runs' own box (the physical inputs' ranges)
// where the model's mean leaves [0, a full barrel of the point's powder]: a transform that says
// there is more powder than the barrel holds, or less than none, between its own runs is not
// admissible, however small its leave-one-out error (which only looks at the runs).
// s must know its full barrel: its prediction flags a mean above it.
double nonPhysicalShare(const Surrogate& s) {
    constexpr int kSample = 1024;
    std::unique_ptr<gsl_qrng, decltype(&gsl_qrng_free)> q(gsl_qrng_alloc(gsl_qrng_sobol, kInputs), gsl_qrng_free);
    auto ws = s.makeWorkspace();
    int bad = 0;
    double u[kInputs];
    for (int i = 0; i < kSample; ++i) {
        gsl_qrng_get(q.get(), u);
        Point x;
        for (size_t k = 0; k < kInputs; ++k) x[k] = s.boxMin()[k] + u[k] * (s.boxMax()[k] - s.boxMin()[k]);
        if (!(x[kMuD] > x[kMuS])) continue;  // not a powder the model answers for
        const auto p = s.predict(x, ws);
        if (!(p.m > 0) || p.overfull) ++bad;
    }
    return static_cast<double>(bad) / kSample;
}
}  // namespace

Surrogate Surrogate::fit(const std::vector<Row>& train, const FitOptions& o, nlohmann::json provenance) {
    if (o.kind == "regimes") return fitRegimes(train, o, std::move(provenance));
    if (o.kind != "rsm" && o.kind != "kriging") throw InputError("kind", o.kind, "rsm, kriging or regimes");
    const auto n = static_cast<Eigen::Index>(train.size());
    if (n < 5) throw InputError("training runs", std::to_string(n), "at least 5 finished, steady runs");
    Surrogate best;
    double bestErr = std::numeric_limits<double>::infinity();
    bool bestAdmissible = false;
    double bestBad = 0;
    const double fullBarrelM3 = fullBarrelIn(provenance);
    nlohmann::json tried = nlohmann::json::array();
    for (const auto& tf : candidates(o.transform, o.similarity)) {
        Surrogate s;
        s.kind_ = o.kind;
        s.tf_ = tf;
        s.setInputs();
        const int d = s.dims();
        for (size_t k = 0; k < kInputs; ++k) {
            s.min_[k] = s.max_[k] = train[0].x[k];
            for (const auto& r : train) s.min_[k] = std::min(s.min_[k], r.x[k]), s.max_[k] = std::max(s.max_[k], r.x[k]);
        }
        double v[kInputs];
        s.derive(train[0].x, v);
        for (int k = 0; k < d; ++k) s.dmin_[static_cast<size_t>(k)] = s.dmax_[static_cast<size_t>(k)] = v[k];
        for (const auto& r : train) {
            s.derive(r.x, v);
            for (size_t k = 0; k < static_cast<size_t>(d); ++k) s.dmin_[k] = std::min(s.dmin_[k], v[k]), s.dmax_[k] = std::max(s.dmax_[k], v[k]);
        }
        for (size_t k = 0; k < static_cast<size_t>(d); ++k) {
            s.umin_[k] = fwd(tf.logInput[k], s.dmin_[k]);
            s.umax_[k] = fwd(tf.logInput[k], s.dmax_[k]);
            if (!(s.umax_[k] > s.umin_[k])) s.umax_[k] = s.umin_[k] + 1;  // a constant input
        }
        auto ko = o.kriging;
        for (const auto& name : o.trendInputs) {
            int at = -1;
            for (int k = 0; k < d; ++k)
                if (s.in_[static_cast<size_t>(k)].name == name) at = k;
            if (at < 0) {
                std::string names;
                for (int k = 0; k < d; ++k) names += (k ? ", " : "") + s.in_[static_cast<size_t>(k)].name;
                throw InputError("trend-inputs", name, "one of this model's inputs: " + names);
            }
            ko.trendInputs.push_back(at);
            ko.trend = Trend::Linear;
        }
        // A linear trend needs its inputs to vary: a constant one is a zero column beside the
        // intercept (e.g. rho and I0, which issue 16's campaigns fix by design).
        if (o.kind == "kriging" && ko.trend == Trend::Linear)
            for (size_t k = 0; k < static_cast<size_t>(d); ++k)
                if ((ko.trendInputs.empty() || std::find(ko.trendInputs.begin(), ko.trendInputs.end(), static_cast<int>(k)) !=
                                                   ko.trendInputs.end()) &&
                    !(s.dmax_[k] > s.dmin_[k]))
                    throw InputError("trend", "linear",
                                     "inputs that vary over the training runs; " + s.in_[k].name + " is " +
                                         formatNumber(s.dmin_[k]) + " in all " + std::to_string(n) +
                                         " (fit with --similarity, which has no rho or I0, or --trend constant)");
        Eigen::MatrixXd Z(n, d);
        Eigen::VectorXd y(n);
        for (Eigen::Index i = 0; i < n; ++i) {
            const auto& r = train[static_cast<size_t>(i)];
            if (tf.logOutput && !(r.m > 0)) throw InputError("loading_kg", formatNumber(r.m), "> 0 for a log transform (run " + r.id + ")");
            double z[kInputs];
            s.scale(r.x, z);
            for (int k = 0; k < d; ++k) Z(i, k) = z[k];
            y(i) = fwd(tf.logOutput, r.m / s.outputScale(r.x));
        }
        // Leave-one-out predictions and the variance of a new run's result, transformed units.
        Eigen::VectorXd looPred(n), looVar(n);
        if (o.kind == "rsm") {
            try {
                s.rsm_ = ResponseSurface::fit(Z, y, o.select);
            } catch (const std::invalid_argument& e) {
                throw InputError(e.what());  // more terms than runs
            }
            const auto& rs = *s.rsm_;
            s.tQuantile_ = rs.dof() > 0 ? gsl_cdf_tdist_Pinv(0.975, rs.dof()) : kNaN;
            if (o.select) {
                const auto loo = ResponseSurface::selectedLoo(Z, y);
                looPred = y - loo.residuals;
                looVar = loo.variances;
            } else {
                for (Eigen::Index i = 0; i < n; ++i) {
                    looPred(i) = y(i) - rs.looResiduals()(i);
                    looVar(i) = rs.residualVariance() / std::max(1 - rs.leverages()(i), 1e-12);
                }
            }
        } else {
            // In log M the relative noise is the noise itself; in M, relative to the typical loading.
            if (o.noise > 0) ko.noiseVarianceMin = tf.logOutput ? o.noise * o.noise : std::pow(o.noise * y.cwiseAbs().mean(), 2);
            try {
                s.kriging_ = Kriging::fit(Z, y, ko);
            } catch (const std::invalid_argument& e) {
                throw InputError(e.what());  // e.g. too few runs for a linear trend
            }
            const auto r = s.kriging_->looResiduals();
            const auto v = s.kriging_->looVariances();
            looPred = y - r;
            looVar = v;
        }
        const double q = o.kind == "rsm" ? s.tQuantile_ : kZ95;
        ErrorStats stats;
        s.loo_ = nlohmann::json::object();
        for (Eigen::Index i = 0; i < n; ++i) {
            const auto& row = train[static_cast<size_t>(i)];
            const double c = s.outputScale(row.x);
            const double m = c * back(tf.logOutput, looPred(i));
            const double sd = std::sqrt(std::max(looVar(i), 0.0));
            const double lo = c * back(tf.logOutput, looPred(i) - q * sd), hi = c * back(tf.logOutput, looPred(i) + q * sd);
            stats.add(row.m, m, lo, hi);
            s.loo_[row.id] = {m, lo, hi};
        }
        const double meanErr = stats.mean().get<double>();
        nlohmann::json t{{"transform", tf.describe()}, {"loo_mean_rel_error", meanErr}};
        s.fullBarrelM3_ = fullBarrelM3;
        const double bad = fullBarrelM3 > 0 ? nonPhysicalShare(s) : 0.0;
        if (fullBarrelM3 > 0) t["non_physical_share"] = bad;
        tried.push_back(t);
        s.validation_ = {{"method", o.kind == "rsm" && o.select
                                        ? "leave-one-out (terms selected anew without each run)"
                                        : "leave-one-out (closed form, hyperparameters and terms fixed)"},
                         {"n", n},
                         {"mean_rel_error", meanErr},
                         {"max_rel_error", stats.maxJson()},
                         {"coverage95", stats.coverage()}};
        // An admissible transform beats any that is not; among equals, the leave-one-out error decides.
        const bool admissible = !(bad > 0);
        if ((admissible && !bestAdmissible) || (admissible == bestAdmissible && meanErr < bestErr))
            bestErr = meanErr, bestAdmissible = admissible, bestBad = bad, best = std::move(s);
    }
    if (!bestAdmissible)
        best.validation_["non_physical"] =
            "every transform tried says less than none or more than a full barrel somewhere in its training box; the one "
            "kept does at " + formatNumber(100 * bestBad) + "% of it: read its answers with care";
    best.validation_["transforms_tried"] = tried;
    best.validation_["transform"] = best.tf_.describe();
    for (const auto& r : train) best.trained_.push_back(r.id);
    best.provenance_ = std::move(provenance);
    best.setFullBarrel();
    return best;
}

Surrogate::Workspace Surrogate::makeWorkspace() const {
    Workspace ws;
    if (rsm_) ws.rsm.assign(rsm_->terms().size(), 0.0);
    if (kriging_) ws.kriging = kriging_->makeWorkspace();
    for (const auto& part : parts_) ws.parts.push_back(part.makeWorkspace());
    return ws;
}

bool Surrogate::inBox(const Point& x) const {
    if (!parts_.empty()) return inBoxRegimes(x);
    double v[kInputs];
    derive(x, v);
    for (size_t k = 0; k < in_.size(); ++k)
        if (v[k] < dmin_[k] || v[k] > dmax_[k]) return false;
    return true;
}

double Surrogate::outsideDistance(const Point& x) const {
    if (!parts_.empty()) return outsideRegimes(x);
    double z[kInputs];
    scale(x, z);
    return distanceOf(z);
}

// From scaled inputs: [0, 1] over the box for kriging, [-1, 1] for a response surface.
double Surrogate::distanceOf(const double* z) const {
    double worst = 0;
    for (size_t k = 0; k < in_.size(); ++k) {
        const double s = kind_ == "rsm" ? 0.5 * (z[k] + 1) : z[k];
        worst = std::max(worst, std::max(-s, s - 1));
    }
    return worst;
}

void Surrogate::requireNearBox(const Point& x, const std::string& label) const {
    const double d = outsideDistance(x);
    if (d <= kMaxExtrapolation) return;
    std::string where;
    for (const auto& w : outsideBox(x)) where += (where.empty() ? "" : "; ") + w;
    throw InputError(label + "point", where,
                     "within " + formatNumber(100 * kMaxExtrapolation) + "% of each input's trained range beyond the box (this one: " +
                         formatNumber(std::round(100 * d)) + "%); run the full model (mixload mixer) there, or pass --extrapolate");
}

std::vector<std::string> Surrogate::outsideBox(const Point& x) const {
    if (!parts_.empty()) return outsideBoxRegimes(x);
    std::vector<std::string> out;
    double v[kInputs];
    derive(x, v);
    for (size_t k = 0; k < in_.size(); ++k)
        if (v[k] < dmin_[k] || v[k] > dmax_[k])
            out.push_back(in_[k].name + " = " + formatNumber(v[k]) + " (trained on " + formatNumber(dmin_[k]) + " .. " +
                          formatNumber(dmax_[k]) + " " + in_[k].unit + ")");
    return out;
}

void Surrogate::setFullBarrel() {
    fullBarrelM3_ = fullBarrelIn(provenance_);
}

Prediction Surrogate::predict(const Point& x, Workspace& ws) const {
    if (!parts_.empty()) return predictRegimes(x, ws);
    double z[kInputs];
    scale(x, z);
    double mean = 0, var = 0, q = kZ95;
    if (rsm_) {
        rsm_->predict(z, ws.rsm.data(), mean, var);
        q = tQuantile_;
    } else {
        kriging_->predict(z, ws.kriging, mean, var);
        // A full run's result scatters by the nugget (steady-detection noise) around the latent mean.
        var += kriging_->processVariance() * kriging_->nugget();
    }
    const double sd = std::sqrt(std::max(var, 0.0)), c = outputScale(x);
    Prediction p;
    p.m = c * back(tf_.logOutput, mean);
    p.lo = c * back(tf_.logOutput, mean - q * sd);
    p.hi = c * back(tf_.logOutput, mean + q * sd);
    physicalBounds(x, p);
    p.inBox = inBox(x);
    p.outside = distanceOf(z);
    return p;
}

void Surrogate::physicalBounds(const Point& x, Prediction& p) const {
    // A loading is never negative: a model of M itself (not of log M) can say so far from its
    // runs, and the answer is then cut at zero and flagged.
    if (p.lo < 0 || p.m < 0) {
        p.clipped = true;
        p.lo = std::max(p.lo, 0.0);
        p.m = std::max(p.m, 0.0);
        p.hi = std::max(p.hi, 0.0);
    }
    if (fullBarrelM3_ > 0) {
        p.fullBarrelKg = x[kRho] * fullBarrelM3_;
        p.overfull = p.m > p.fullBarrelKg;
        p.lo = std::min(p.lo, p.fullBarrelKg);
        p.hi = std::min(p.hi, p.fullBarrelKg);
    }
}

Difference Surrogate::predictDifference(const Point& a, const Point& b) const {
    if (!parts_.empty()) return predictDifferenceRegimes(a, b);
    double za[kInputs], zb[kInputs];
    scale(a, za);
    scale(b, zb);
    Eigen::Vector2d mean;
    Eigen::Matrix2d cov;
    double noise = 0, q = kZ95;
    if (rsm_) {
        rsm_->predictPair(za, zb, mean, cov);
        noise = rsm_->residualVariance();
        q = tQuantile_;
    } else {
        kriging_->predictPair(za, zb, mean, cov);
        noise = kriging_->processVariance() * kriging_->nugget();
    }
    const double ca = outputScale(a), cb = outputScale(b);
    Difference d;
    d.dm = cb * back(tf_.logOutput, mean(1)) - ca * back(tf_.logOutput, mean(0));
    const double va = cov(0, 0) + noise, vb = cov(1, 1) + noise;
    d.correlation = cov(0, 1) / std::sqrt(std::max(va * vb, 1e-300));
    if (std::isnan(q)) {
        d.lo = d.hi = d.loIndependent = d.hiIndependent = kNaN;
        return d;
    }
    // The difference of two (log-)normal results has no closed-form quantiles: take them from a
    // fixed quasi-random sample (Halton bases 2 and 3 through the normal quantile), so the answer
    // is deterministic. The scale q / z95 makes a response surface's t interval.
    const double sa = std::sqrt(va), sb = std::sqrt(vb), rho = std::clamp(cov(0, 1) / (sa * sb), -1.0, 1.0);
    const double widen = q / kZ95;
    constexpr int kDraws = 4096;
    std::vector<double> dep(kDraws), ind(kDraws);
    const auto halton = [](int i, int base) {
        double f = 1, r = 0;
        for (; i > 0; i /= base) f /= base, r += f * (i % base);
        return r;
    };
    for (int i = 0; i < kDraws; ++i) {
        const double u1 = gsl_cdf_ugaussian_Pinv(halton(i + 1, 2)), u2 = gsl_cdf_ugaussian_Pinv(halton(i + 1, 3));
        const double ya = mean(0) + widen * sa * u1;
        const double ybCorr = mean(1) + widen * sb * (rho * u1 + std::sqrt(1 - rho * rho) * u2);
        const double ybInd = mean(1) + widen * sb * u2;
        const double ma = ca * back(tf_.logOutput, ya);
        dep[static_cast<size_t>(i)] = cb * back(tf_.logOutput, ybCorr) - ma;
        ind[static_cast<size_t>(i)] = cb * back(tf_.logOutput, ybInd) - ma;
    }
    d.lo = percentile(dep, 0.025);
    d.hi = percentile(dep, 0.975);
    d.loIndependent = percentile(ind, 0.025);
    d.hiIndependent = percentile(ind, 0.975);
    return d;
}

std::vector<std::string> Surrogate::warnings() const {
    std::vector<std::string> out;
    if (validation_.contains("non_physical")) out.push_back(validation_["non_physical"].get<std::string>());
    for (size_t r = 0; r < parts_.size(); ++r)
        for (const auto& w : parts_[r].warnings()) out.push_back(std::string(regimeName(static_cast<Regime>(r))) + " part: " + w);
    if (!kriging_) return out;
    // The kriging model numbers its inputs; name them.
    for (auto w : kriging_->warnings()) {
        std::smatch m;
        if (std::regex_search(w, m, std::regex("length scale (\\d+)"))) {
            const auto k = static_cast<size_t>(std::stoi(m[1]));
            if (k < in_.size()) w = std::string(m.prefix()) + "length scale of " + in_[k].name + std::string(m.suffix());
        }
        out.push_back(w);
    }
    return out;
}

nlohmann::json Surrogate::toJson() const {
    nlohmann::json inputs = nlohmann::json::array(), model = nlohmann::json::array();
    for (size_t k = 0; k < kInputs; ++k)
        inputs.push_back({{"name", kInputSpecs[k].name}, {"unit", kInputSpecs[k].unit}, {"min", min_[k]}, {"max", max_[k]}});
    for (size_t k = 0; k < in_.size(); ++k)
        model.push_back({{"name", in_[k].name},
                         {"unit", in_[k].unit},
                         {"min", dmin_[k]},
                         {"max", dmax_[k]},
                         {"log", tf_.logInput[k]},
                         {"scaled_min", umin_[k]},
                         {"scaled_max", umax_[k]}});
    nlohmann::json j{{"schema", kSchema},
                     {"schema_version", kModelSchemaVersion},
                     {"kind", kind_},
                     {"inputs", inputs},
                     {"similarity", tf_.similarity},
                     {"model_inputs", model},
                     {"output", {{"name", kOutputName}, {"unit", "kg"}, {"log", tf_.logOutput}, {"per_rho", tf_.similarity}}},
                     {"model", !parts_.empty() ? regimesJson() : rsm_ ? rsm_->toJson() : kriging_->toJson()},
                     {"t_quantile", rsm_ ? nlohmann::json(tQuantile_) : nlohmann::json()},
                     {"training_ids", trained_},
                     {"validation", validation_},
                     {"loo", loo_},
                     {"provenance", provenance_},
                     {"checks", checks_}};
    return j;
}

Surrogate Surrogate::fromJson(const nlohmann::json& j) {
    const auto need = [&](const nlohmann::json& o, const char* k) -> const nlohmann::json& {
        if (!o.is_object() || !o.contains(k)) throw std::runtime_error(std::string("missing field '") + k + "'");
        return o[k];
    };
    if (need(j, "schema") != kSchema) throw std::runtime_error("not a mixload surrogate (schema is not mixload-surrogate)");
    const int v = need(j, "schema_version").get<int>();
    if (v != kModelSchemaVersion && v != 1)
        throw std::runtime_error("model schema version " + std::to_string(v) + ", this mixload reads " +
                                 std::to_string(kModelSchemaVersion));
    Surrogate s;
    s.kind_ = need(j, "kind").get<std::string>();
    if (s.kind_ != "rsm" && s.kind_ != "kriging" && s.kind_ != "regimes")
        throw std::runtime_error("unknown kind '" + s.kind_ + "'");
    const auto& inputs = need(j, "inputs");
    if (!inputs.is_array() || inputs.size() != kInputs) throw std::runtime_error("field 'inputs' must list the 7 inputs");
    for (size_t k = 0; k < kInputs; ++k) {
        const auto& in = inputs[k];
        if (need(in, "name") != kInputSpecs[k].name)
            throw std::runtime_error("input " + std::to_string(k) + " is '" + in["name"].get<std::string>() + "', expected " +
                                     kInputSpecs[k].name);
        s.min_[k] = need(in, "min");
        s.max_[k] = need(in, "max");
    }
    // Version 1 models took the physical inputs themselves and kept their scaling in "inputs".
    s.tf_.similarity = v == 1 ? false : need(j, "similarity").get<bool>();
    s.setInputs();
    const auto& model = v == 1 ? inputs : need(j, "model_inputs");
    if (!model.is_array() || model.size() != s.in_.size())
        throw std::runtime_error("field 'model_inputs' must list the " + std::to_string(s.in_.size()) + " model inputs");
    for (size_t k = 0; k < s.in_.size(); ++k) {
        const auto& in = model[k];
        if (need(in, "name") != s.in_[k].name)
            throw std::runtime_error("model input " + std::to_string(k) + " is '" + in["name"].get<std::string>() + "', expected " +
                                     s.in_[k].name);
        s.dmin_[k] = need(in, "min");
        s.dmax_[k] = need(in, "max");
        s.tf_.logInput[k] = need(in, "log");
        s.umin_[k] = need(in, "scaled_min");
        s.umax_[k] = need(in, "scaled_max");
    }
    s.tf_.logOutput = need(need(j, "output"), "log");
    const auto& fitted = need(j, "model");
    if (s.kind_ == "regimes") {
        s.regimesFromJson(fitted);
    } else if (s.kind_ == "rsm") {
        s.rsm_ = ResponseSurface::fromJson(fitted);
        if (s.rsm_->dims() != s.dims()) throw std::runtime_error("the response surface's dimension is not the model inputs' count");
        s.tQuantile_ = need(j, "t_quantile").is_null() ? kNaN : j["t_quantile"].get<double>();
    } else {
        s.kriging_ = Kriging::fromJson(fitted);
        if (s.kriging_->dims() != s.dims()) throw std::runtime_error("the kriging model's dimension is not the model inputs' count");
    }
    s.trained_ = need(j, "training_ids").get<std::vector<std::string>>();
    s.validation_ = need(j, "validation");
    s.loo_ = need(j, "loo");
    s.provenance_ = need(j, "provenance");
    s.setFullBarrel();
    s.checks_ = need(j, "checks");
    return s;
}

Surrogate Surrogate::load(const std::filesystem::path& file) {
    if (!std::filesystem::is_regular_file(file)) throw InputError("model", file.string(), "an existing model file");
    try {
        return fromJson(nlohmann::json::parse(readFile(file)));
    } catch (const std::exception& e) {
        throw InputError(file.string() + ": " + e.what());
    }
}

void Surrogate::save(const std::filesystem::path& file) const { writeFileAtomic(file, toJson().dump(1) + "\n"); }

std::string Surrogate::sourceLabel() const {
    const auto src = provenance_.value("source", nlohmann::json::object());
    const auto base = src.value("base", nlohmann::json::object());
    if (base.value("kind", std::string()) != "mixer") return "source not recorded";
    std::ostringstream os;
    os << "scene " << base.value("scene", std::string("?")) << ", " << base.value("method", std::string("?")) << ", ";
    if (base.contains("cell_size_m")) os << base["cell_size_m"].get<double>() << " m mesh";
    else if (provenance_.contains("cell_size_m"))
        os << base.value("mesh", std::string("?")) << " mesh, " << provenance_["cell_size_m"].get<double>() << " m";
    else os << base.value("mesh", std::string("?")) << " mesh";
    // Campaign bases written before the O-grid carry no mesher: they ran on the snappy mesh.
    os << " (" << base.value("mesher", std::string("snappy")) << "), campaign " << src.value("campaign", std::string("?"))
       << ", " << provenance_.value("runs_usable", 0) << " runs";
    return os.str();
}

}  // namespace mixload::surrogates
