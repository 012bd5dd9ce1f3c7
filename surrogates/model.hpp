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

inline constexpr int kModelSchemaVersion = 1;

struct Transform {
    bool logOutput = false;
    std::array<bool, kInputs> logInput{};
    std::string describe() const;
};

struct FitOptions {
    std::string kind = "kriging";    // rsm | kriging
    std::string transform = "auto";  // auto (chosen by leave-one-out error) | none | log
    bool select = true;              // rsm: forward term selection by PRESS
    KrigingOptions kriging;
};

struct Prediction {
    double m = 0;              // [kg]
    double lo = 0, hi = 0;     // 95% interval for a full run's result [kg] (NaN if none)
    bool inBox = true;         // every input inside the training box
};

class Surrogate {
public:
    // Per-thread scratch for the allocation-free prediction.
    struct Workspace {
        std::vector<double> rsm;
        Kriging::Workspace kriging;
    };

    static Surrogate fit(const std::vector<Row>& train, const FitOptions& o, nlohmann::json provenance);

    Workspace makeWorkspace() const;
    Prediction predict(const Point& x, Workspace& ws) const;  // no heap allocation
    bool inBox(const Point& x) const;
    // Inputs outside the training box as "name = value (box lo..hi unit)".
    std::vector<std::string> outsideBox(const Point& x) const;

    const std::string& kind() const { return kind_; }
    const Transform& transform() const { return tf_; }
    const Point& boxMin() const { return min_; }
    const Point& boxMax() const { return max_; }
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
    void scale(const Point& x, double* z) const;
    std::string kind_;
    Transform tf_;
    Point min_{}, max_{};        // training box, physical units
    Point umin_{}, umax_{};      // the box in transformed units
    std::optional<ResponseSurface> rsm_;
    std::optional<Kriging> kriging_;
    double tQuantile_ = 0;       // rsm: Student t 97.5% quantile at its dof
    std::vector<std::string> trained_;
    nlohmann::json validation_, provenance_, checks_ = nlohmann::json::array(), loo_;
};

}  // namespace mixload::surrogates
