// SPDX-License-Identifier: GPL-3.0-or-later
#include "model.hpp"

#include <gsl/gsl_cdf.h>

#include <cmath>
#include <limits>
#include <regex>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "error_stats.hpp"

namespace mixload::surrogates {

namespace {

constexpr const char* kSchema = "mixload-surrogate";
constexpr double kZ95 = 1.959963984540054;
const double kNaN = std::numeric_limits<double>::quiet_NaN();

bool dimensional(int k) { return std::string(kInputSpecs[static_cast<size_t>(k)].unit) != "1"; }

std::vector<Transform> candidates(const std::string& mode) {
    Transform none, logs;
    logs.logOutput = true;
    for (int k = 0; k < kInputs; ++k) logs.logInput[static_cast<size_t>(k)] = dimensional(k);
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

std::string Transform::describe() const {
    std::string s = logOutput ? "log M" : "M";
    std::string in;
    for (int k = 0; k < kInputs; ++k)
        if (logInput[static_cast<size_t>(k)]) in += std::string(in.empty() ? "" : ", ") + kInputSpecs[static_cast<size_t>(k)].name;
    return s + (in.empty() ? " of linear inputs" : " of log(" + in + ")");
}

void Surrogate::scale(const Point& x, double* z) const {
    for (size_t k = 0; k < kInputs; ++k) {
        const double u = fwd(tf_.logInput[k], x[k]);
        const double s = (u - umin_[k]) / (umax_[k] - umin_[k]);
        // Response surfaces live on [-1, 1] (orthogonal-ish terms), kriging on [0, 1].
        z[k] = kind_ == "rsm" ? 2 * s - 1 : s;
    }
}

Surrogate Surrogate::fit(const std::vector<Row>& train, const FitOptions& o, nlohmann::json provenance) {
    if (o.kind != "rsm" && o.kind != "kriging") throw InputError("kind", o.kind, "rsm or kriging");
    const auto n = static_cast<Eigen::Index>(train.size());
    if (n < 5) throw InputError("training runs", std::to_string(n), "at least 5 finished, steady runs");
    Surrogate best;
    double bestErr = std::numeric_limits<double>::infinity();
    nlohmann::json tried = nlohmann::json::array();
    for (const auto& tf : candidates(o.transform)) {
        Surrogate s;
        s.kind_ = o.kind;
        s.tf_ = tf;
        for (size_t k = 0; k < kInputs; ++k) {
            s.min_[k] = s.max_[k] = train[0].x[k];
            for (const auto& r : train) s.min_[k] = std::min(s.min_[k], r.x[k]), s.max_[k] = std::max(s.max_[k], r.x[k]);
            s.umin_[k] = fwd(tf.logInput[k], s.min_[k]);
            s.umax_[k] = fwd(tf.logInput[k], s.max_[k]);
            if (!(s.umax_[k] > s.umin_[k])) s.umax_[k] = s.umin_[k] + 1;  // a constant input
        }
        Eigen::MatrixXd Z(n, kInputs);
        Eigen::VectorXd y(n);
        for (Eigen::Index i = 0; i < n; ++i) {
            const auto& r = train[static_cast<size_t>(i)];
            if (tf.logOutput && !(r.m > 0)) throw InputError("loading_kg", formatNumber(r.m), "> 0 for a log transform (run " + r.id + ")");
            double z[kInputs];
            s.scale(r.x, z);
            for (int k = 0; k < kInputs; ++k) Z(i, k) = z[k];
            y(i) = fwd(tf.logOutput, r.m);
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
            for (Eigen::Index i = 0; i < n; ++i) {
                looPred(i) = y(i) - rs.looResiduals()(i);
                looVar(i) = rs.residualVariance() / std::max(1 - rs.leverages()(i), 1e-12);
            }
        } else {
            try {
                s.kriging_ = Kriging::fit(Z, y, o.kriging);
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
            const double m = back(tf.logOutput, looPred(i));
            const double sd = std::sqrt(std::max(looVar(i), 0.0));
            const double lo = back(tf.logOutput, looPred(i) - q * sd), hi = back(tf.logOutput, looPred(i) + q * sd);
            stats.add(row.m, m, lo, hi);
            s.loo_[row.id] = {m, lo, hi};
        }
        const double meanErr = stats.mean().get<double>();
        tried.push_back({{"transform", tf.describe()}, {"loo_mean_rel_error", meanErr}});
        s.validation_ = {{"method", "leave-one-out (closed form, hyperparameters and terms fixed)"},
                         {"n", n},
                         {"mean_rel_error", meanErr},
                         {"max_rel_error", stats.maxJson()},
                         {"coverage95", stats.coverage()}};
        if (meanErr < bestErr) bestErr = meanErr, best = std::move(s);
    }
    best.validation_["transforms_tried"] = tried;
    best.validation_["transform"] = best.tf_.describe();
    for (const auto& r : train) best.trained_.push_back(r.id);
    best.provenance_ = std::move(provenance);
    return best;
}

Surrogate::Workspace Surrogate::makeWorkspace() const {
    Workspace ws;
    if (rsm_) ws.rsm.assign(rsm_->terms().size(), 0.0);
    if (kriging_) ws.kriging = kriging_->makeWorkspace();
    return ws;
}

bool Surrogate::inBox(const Point& x) const {
    for (size_t k = 0; k < kInputs; ++k)
        if (x[k] < min_[k] || x[k] > max_[k]) return false;
    return true;
}

std::vector<std::string> Surrogate::outsideBox(const Point& x) const {
    std::vector<std::string> out;
    for (size_t k = 0; k < kInputs; ++k)
        if (x[k] < min_[k] || x[k] > max_[k])
            out.push_back(std::string(kInputSpecs[k].name) + " = " + formatNumber(x[k]) + " (trained on " +
                          formatNumber(min_[k]) + " .. " + formatNumber(max_[k]) + " " + kInputSpecs[k].unit + ")");
    return out;
}

Prediction Surrogate::predict(const Point& x, Workspace& ws) const {
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
    const double sd = std::sqrt(std::max(var, 0.0));
    Prediction p;
    p.m = back(tf_.logOutput, mean);
    p.lo = back(tf_.logOutput, mean - q * sd);
    p.hi = back(tf_.logOutput, mean + q * sd);
    p.inBox = inBox(x);
    return p;
}

std::vector<std::string> Surrogate::warnings() const {
    std::vector<std::string> out;
    if (!kriging_) return out;
    // The kriging model numbers its inputs; name them.
    for (auto w : kriging_->warnings()) {
        std::smatch m;
        if (std::regex_search(w, m, std::regex("length scale (\\d+)"))) {
            const auto k = static_cast<size_t>(std::stoi(m[1]));
            if (k < kInputs) w = std::string(m.prefix()) + "length scale of " + kInputSpecs[k].name + std::string(m.suffix());
        }
        out.push_back(w);
    }
    return out;
}

nlohmann::json Surrogate::toJson() const {
    nlohmann::json inputs = nlohmann::json::array();
    for (size_t k = 0; k < kInputs; ++k)
        inputs.push_back({{"name", kInputSpecs[k].name},
                          {"unit", kInputSpecs[k].unit},
                          {"min", min_[k]},
                          {"max", max_[k]},
                          {"log", tf_.logInput[k]},
                          {"scaled_min", umin_[k]},
                          {"scaled_max", umax_[k]}});
    nlohmann::json j{{"schema", kSchema},
                     {"schema_version", kModelSchemaVersion},
                     {"kind", kind_},
                     {"inputs", inputs},
                     {"output", {{"name", kOutputName}, {"unit", "kg"}, {"log", tf_.logOutput}}},
                     {"model", rsm_ ? rsm_->toJson() : kriging_->toJson()},
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
    if (v != kModelSchemaVersion)
        throw std::runtime_error("model schema version " + std::to_string(v) + ", this mixload reads " +
                                 std::to_string(kModelSchemaVersion));
    Surrogate s;
    s.kind_ = need(j, "kind").get<std::string>();
    if (s.kind_ != "rsm" && s.kind_ != "kriging") throw std::runtime_error("unknown kind '" + s.kind_ + "'");
    const auto& inputs = need(j, "inputs");
    if (!inputs.is_array() || inputs.size() != kInputs) throw std::runtime_error("field 'inputs' must list the 7 inputs");
    for (size_t k = 0; k < kInputs; ++k) {
        const auto& in = inputs[k];
        if (need(in, "name") != kInputSpecs[k].name)
            throw std::runtime_error("input " + std::to_string(k) + " is '" + in["name"].get<std::string>() + "', expected " +
                                     kInputSpecs[k].name);
        s.min_[k] = need(in, "min");
        s.max_[k] = need(in, "max");
        s.tf_.logInput[k] = need(in, "log");
        s.umin_[k] = need(in, "scaled_min");
        s.umax_[k] = need(in, "scaled_max");
    }
    s.tf_.logOutput = need(need(j, "output"), "log");
    const auto& model = need(j, "model");
    if (s.kind_ == "rsm") {
        s.rsm_ = ResponseSurface::fromJson(model);
        s.tQuantile_ = need(j, "t_quantile").is_null() ? kNaN : j["t_quantile"].get<double>();
    } else {
        s.kriging_ = Kriging::fromJson(model);
    }
    s.trained_ = need(j, "training_ids").get<std::vector<std::string>>();
    s.validation_ = need(j, "validation");
    s.loo_ = need(j, "loo");
    s.provenance_ = need(j, "provenance");
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
    else os << base.value("mesh", std::string("?")) << " mesh";
    // Campaign bases written before the O-grid carry no mesher: they ran on the snappy mesh.
    os << " (" << base.value("mesher", std::string("snappy")) << "), campaign " << src.value("campaign", std::string("?"))
       << ", " << provenance_.value("runs_usable", 0) << " runs";
    return os.str();
}

}  // namespace mixload::surrogates
