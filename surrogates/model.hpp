// SPDX-License-Identifier: GPL-3.0-or-later
// A fitted surrogate of the mixer loading M(mu_s, mu_d, I0, d, rho, feed, rpm): the transform and
// scaling of the inputs, a response surface or a kriging model, its training box, validation
// statistics, provenance and check history. Stored as one JSON file (schema "mixload-surrogate").
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "inputs.hpp"
#include "kriging/kriging.hpp"
#include "rsm/rsm.hpp"
#include "table.hpp"

namespace mixload::surrogates {

// 2: the model's own inputs ("model_inputs"), which may be ratios of the physical ones; 1 is read too.
inline constexpr int kModelSchemaVersion = 2;

// One input of the fitted model: a physical input, or the ratio of two that the physics says act
// only together. With `similarity`, mu(I) sees d and I0 only as d/I0, and the bulk density scales out
// of the powder's motion, so the model learns the bed's volume M/rho as a function of feed/rho
// (measured on the calibrated scene: README, "Exact similarity").
struct ModelInput {
    std::string name, unit;
    int num = 0;     // physical input in the numerator (index into kInputSpecs)
    int den = -1;    // physical input in the denominator, or -1
    bool positive = true;
};
std::vector<ModelInput> modelInputs(bool similarity);

struct Transform {
    bool similarity = false;           // inputs mu_s, mu_d, d/i0, feed/rho, rpm; output M/rho
    bool logOutput = false;
    std::array<bool, kInputs> logInput{};  // by model input
    std::string describe() const;
};

struct FitOptions {
    // rsm | kriging | regimes (a kriging model per flow regime, surrogates/regime.hpp: bed on the
    // runs up to the film's boundary, transition on every run, film on the film's runs; each
    // part's transform and trend chosen by leave-one-out error on its own regime's runs; blended
    // in rpm over kRegimeBlendRpm at the boundaries)
    std::string kind = "kriging";
    std::string transform = "auto";  // auto (chosen by leave-one-out error) | none | log
    bool similarity = false;         // fit M/rho in the similarity variables (Transform::similarity)
    // Relative scatter of a run's loading (the steady test's label noise, about 0.01): kriging's
    // nugget is kept at or above it (KrigingOptions::noiseVarianceMin; 0: no floor).
    double noise = 0;
    bool select = true;              // rsm: forward term selection by PRESS
    // kriging: a linear trend in these model inputs only (names as inputNames() gives them, e.g.
    // "feed/rho", "rpm"); empty: kriging.trend decides (constant, or linear in every input).
    std::vector<std::string> trendInputs;
    KrigingOptions kriging;
};

// Beyond this distance from the training box (a share of an input's trained range) the tools
// refuse to answer unless told to extrapolate: a kriging model there returns its trend, and a
// response surface its quadratic, neither of which knows the physics (README, Surrogates).
inline constexpr double kMaxExtrapolation = 0.25;

struct Prediction {
    double m = 0;              // [kg]
    double lo = 0, hi = 0;     // 95% interval for a full run's result [kg] (NaN if none)
    bool inBox = true;         // every input inside the training box
    // How far the point lies outside the box: the largest excess of a model input beyond the
    // box, as a share of that input's trained range (in the model's own, possibly log, units).
    double outside = 0;
    bool clipped = false;      // the mean or the interval fell below zero and was set to 0
    // A full barrel of this powder (its bulk density times the barrel's open volume, when the model
    // knows its scene's): no loading exceeds it. The interval is cut there, and a mean above it is
    // flagged: the model is not valid at this point.
    double fullBarrelKg = 0;   // 0: unknown
    bool overfull = false;
};

// The difference of two predictions, M(b) - M(a), and the 95% interval of the difference between
// two full runs' results there: the model's errors at the two points are correlated (for nearby
// formulations, mostly shared), each run's own scatter (the nugget) is not.
struct Difference {
    double dm = 0, lo = 0, hi = 0;   // [kg]; lo, hi NaN when the model has no interval
    double correlation = 0;          // of the two predictions' errors, transformed units
    double loIndependent = 0, hiIndependent = 0;  // the same interval with the errors taken as independent
};

class Surrogate {
public:
    // Per-thread scratch for the allocation-free prediction.
    struct Workspace {
        std::vector<double> rsm;
        Kriging::Workspace kriging;
        std::vector<Workspace> parts;  // regimes
    };

    static Surrogate fit(const std::vector<Row>& train, const FitOptions& o, nlohmann::json provenance);

    Workspace makeWorkspace() const;
    Prediction predict(const Point& x, Workspace& ws) const;  // no heap allocation
    // The model's own coordinates of x (its inputs, transformed and scaled to the training box):
    // where another regression on the same runs should see them too.
    std::vector<double> coordinates(const Point& x) const;
    Difference predictDifference(const Point& a, const Point& b) const;  // allocates
    // Inside the training box of the model's own inputs (with similarity, a density outside the
    // trained range is inside when feed/rho is).
    bool inBox(const Point& x) const;
    // Prediction::outside for x, without predicting.
    double outsideDistance(const Point& x) const;
    // Throws InputError naming the inputs outside the box when x lies more than kMaxExtrapolation
    // beyond it; label prefixes the field ("base ", "new ").
    void requireNearBox(const Point& x, const std::string& label = "") const;
    // Model inputs outside the training box as "name = value (box lo..hi unit)".
    std::vector<std::string> outsideBox(const Point& x) const;

    const std::string& kind() const { return kind_; }
    // regimes: the bed, transition and film models (empty for other kinds).
    const std::vector<Surrogate>& parts() const { return parts_; }
    const Transform& transform() const { return tf_; }
    // The physical inputs' range over the training runs.
    const Point& boxMin() const { return min_; }
    const Point& boxMax() const { return max_; }
    const std::vector<ModelInput>& inputs() const { return in_; }
    const std::vector<std::string>& trainingIds() const { return trained_; }
    const nlohmann::json& validation() const { return validation_; }
    const nlohmann::json& provenance() const { return provenance_; }
    // What the model stands for, from its provenance: "scene gcm250, mrf, 0.01 m mesh (snappy),
    // campaign mixer-avicel, 56 runs" (a prediction is only as good as the scene it learnt).
    std::string sourceLabel() const;
    nlohmann::json& checks() { return checks_; }
    const nlohmann::json& checkHistory() const { return checks_; }
    std::vector<std::string> warnings() const;
    // LOO errors of the training runs, by id: {id: [predicted, lo, hi]}.
    const nlohmann::json& loo() const { return loo_; }

    nlohmann::json toJson() const;
    // Throws std::runtime_error naming the field on a wrong schema, version or missing field.
    static Surrogate fromJson(const nlohmann::json& j);
    static Surrogate load(const std::filesystem::path& file);  // InputError naming the file
    void save(const std::filesystem::path& file) const;        // atomic

private:
    static Surrogate fitRegimes(const std::vector<Row>& train, const FitOptions& o, nlohmann::json provenance);
    Prediction predictRegimes(const Point& x, Workspace& ws) const;
    Difference predictDifferenceRegimes(const Point& a, const Point& b) const;
    nlohmann::json regimesJson() const;
    // A regime model's point is inside when it is inside the box of every part that answers it.
    bool inBoxRegimes(const Point& x) const;
    double outsideRegimes(const Point& x) const;
    std::vector<std::string> outsideBoxRegimes(const Point& x) const;
    void regimesFromJson(const nlohmann::json& model);
    void physicalBounds(const Point& x, Prediction& p) const;  // clip at zero and at a full barrel, flagged
    void derive(const Point& x, double* v) const;  // the model inputs, physical units
    double distanceOf(const double* z) const;      // Prediction::outside from scaled inputs
    void scale(const Point& x, double* z) const;
    double outputScale(const Point& x) const { return tf_.similarity ? x[kRho] : 1.0; }  // M = scale * model output
    void setInputs();
    void setFullBarrel();  // from the provenance (fit and load alike)
    int dims() const { return static_cast<int>(in_.size()); }
    std::string kind_;
    Transform tf_;
    std::vector<ModelInput> in_;
    Point min_{}, max_{};        // training range of the physical inputs
    Point dmin_{}, dmax_{};      // training box of the model inputs (first dims() entries)
    Point umin_{}, umax_{};      // the same box in transformed units
    std::optional<ResponseSurface> rsm_;
    std::optional<Kriging> kriging_;
    std::vector<Surrogate> parts_;  // regimes: bed, transition, film
    double tQuantile_ = 0;       // rsm: Student t 97.5% quantile at its dof
    double fullBarrelM3_ = 0;    // provenance "full_barrel_m3": the scene's open barrel volume (0: unknown)
    std::vector<std::string> trained_;
    nlohmann::json validation_, provenance_, checks_ = nlohmann::json::array(), loo_;
};

}  // namespace mixload::surrogates
