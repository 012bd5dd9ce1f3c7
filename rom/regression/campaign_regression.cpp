// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/regression/campaign_regression.hpp"

#include <chrono>
#include <cmath>
#include <optional>

#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "kriging/kriging.hpp"
#include "kriging/unit_box.hpp"
#include "rom/galerkin/collapse_shape.hpp"
#include "rom/operators/alpha_transport.hpp"
#include "rom/operators/fv_mesh.hpp"
#include "rom/regression/pod_regression.hpp"
#include "store/campaign_fields.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::rom {

namespace fs = std::filesystem;

namespace {
using Clock = std::chrono::steady_clock;

// Leave-one-out rows of X and y.
Eigen::MatrixXd without(const Eigen::MatrixXd& m, Eigen::Index i) {
    Eigen::MatrixXd out(m.rows() - 1, m.cols());
    out << m.topRows(i), m.bottomRows(m.rows() - i - 1);
    return out;
}

// A campaign's finished runs with snapshots: their varying inputs X, last stored alpha F (cells x
// runs) and recorded quantities Q, and what reads a quantity from a field.
struct CampaignFields {
    std::vector<store::LedgerRun> runs;
    std::optional<store::SnapshotFile> source;  // the shared mesh and the scene's params
    std::vector<std::string> inputs, qois;
    Eigen::MatrixXd X, F, Q;
    Eigen::MatrixXd U;        // 3 cells x runs: the velocities, when every run kept one
    Eigen::VectorXd wU;       // their weights: each cell's volume for each component
    std::vector<double> rho;  // mixer: each run's bulk density
    bool mixer = false;
    std::string scene;
    FvMesh mesh;
    std::optional<CollapseShape> shape;

    static CampaignFields load(const fs::path& ledger, const std::string& campaign) {
        CampaignFields c;
        // A run's own snapshots, or the campaign's kept fields once its directory is gone.
        auto finals = store::campaignFinalFields(ledger, campaign);
        for (const auto& f : finals.runs) c.runs.push_back(f.run);
        if (c.runs.size() < 3)
            throw InputError("campaign", campaign, "three or more finished runs with snapshots (campaign run --snapshots)");
        for (const auto& [k, v] : c.runs.front().params.items()) {
            if (!v.is_number()) continue;
            bool varies = false;
            for (const auto& r : c.runs) varies = varies || r.params.at(k).get<double>() != v.get<double>();
            if (varies) c.inputs.push_back(k);
        }
        if (c.inputs.empty()) throw InputError("campaign", campaign, "a design whose inputs vary");
        c.source.emplace(finals.meshSource);
        c.scene = c.source->params().value("scene", std::string());
        c.mixer = c.scene == "mixer3d";
        if (!c.mixer && c.scene != "collapse2d") throw InputError("scene", c.scene, "mixer3d or collapse2d runs");
        c.mesh = FvMesh::fromCase(*c.source);
        if (!c.mixer) c.shape = CollapseShape::fromCase(*c.source);
        c.qois = c.mixer ? std::vector<std::string>{"loading_kg"} : std::vector<std::string>{"runout_star", "height_star"};
        const auto n = static_cast<Eigen::Index>(c.runs.size()), d = static_cast<Eigen::Index>(c.inputs.size());
        c.X.resize(n, d);
        c.F.resize(c.mesh.cells, n);
        c.Q.resize(n, static_cast<Eigen::Index>(c.qois.size()));
        for (Eigen::Index i = 0; i < n; ++i) {
            const auto& f = finals.runs[static_cast<size_t>(i)];
            for (Eigen::Index k = 0; k < d; ++k) c.X(i, k) = f.run.params.at(c.inputs[static_cast<size_t>(k)]).get<double>();
            c.F.col(i) = f.alpha;
            for (size_t q = 0; q < c.qois.size(); ++q) c.Q(i, static_cast<Eigen::Index>(q)) = f.run.result.at(c.qois[q]).get<double>();
            c.rho.push_back(c.mixer ? f.bulkDensity : 0.0);
        }
        bool everyU = true;
        for (const auto& f : finals.runs) everyU = everyU && f.U.size() == 3 * c.mesh.cells && f.U.allFinite();
        if (everyU) {
            c.U.resize(3 * c.mesh.cells, n);
            for (Eigen::Index i = 0; i < n; ++i) c.U.col(i) = finals.runs[static_cast<size_t>(i)].U;
            c.wU = c.mesh.V.replicate(1, 3).transpose().reshaped();
        }
        return c;
    }

    // What a field says of a run: the instantaneous loading (at bulk density rho) or the
    // deposit's runout and height.
    std::vector<double> quantities(const Eigen::VectorXd& alpha, double bulkDensity) const {
        if (mixer) return {bulkDensity * clampFraction(alpha).dot(mesh.V)};
        return {shape->runoutStar(mesh, alpha), shape->heightStar(mesh, alpha)};
    }
};
}  // namespace

nlohmann::json campaignRegressionCheck(const fs::path& ledger, const std::string& campaign, const RegressionCheckOptions& o) {
    const auto c = CampaignFields::load(ledger, campaign);
    const auto& X = c.X;
    const auto n = X.rows(), d = X.cols();
    nlohmann::json rows = nlohmann::json::array();
    std::vector<double> regErr(c.qois.size(), 0), krigErr(c.qois.size(), 0), fieldErr(c.qois.size(), 0);
    double alphaErr = 0, uErr = 0, predictSeconds = 0;
    const auto box = surrogates::UnitBox::of(X);
    for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::MatrixXd Xt = without(X, i);
        const Eigen::MatrixXd Ft = without(c.F.transpose(), i).transpose();
        const auto reg = PodRegression::fit(Xt, Ft, c.mesh.V, o.modes, o.energy);
        const auto t0 = Clock::now();
        const Eigen::VectorXd alpha = reg.predict(X.row(i).transpose());
        const auto q = c.quantities(alpha, c.rho[static_cast<size_t>(i)]);
        predictSeconds += secondsSince(t0) / static_cast<double>(n);
        const auto qStored = c.quantities(c.F.col(i), c.rho[static_cast<size_t>(i)]);
        const double aErr = std::sqrt((alpha - c.F.col(i)).cwiseAbs2().dot(c.mesh.V) / c.F.col(i).cwiseAbs2().dot(c.mesh.V));
        alphaErr += aErr / static_cast<double>(n);
        nlohmann::json row{{"run", c.runs[static_cast<size_t>(i)].index}, {"alpha_error", aErr}, {"modes", reg.modes()}};
        if (c.U.size() > 0) {
            const Eigen::MatrixXd Ut = without(c.U.transpose(), i).transpose();
            const Eigen::VectorXd u = PodRegression::fit(Xt, Ut, c.wU, o.modes, o.energy).predict(X.row(i).transpose());
            const double e = std::sqrt((u - c.U.col(i)).cwiseAbs2().dot(c.wU) / c.U.col(i).cwiseAbs2().dot(c.wU));
            row["u_error"] = e;
            uErr += e / static_cast<double>(n);
        }
        for (Eigen::Index k = 0; k < d; ++k) row[c.inputs[static_cast<size_t>(k)]] = X(i, k);
        const Eigen::MatrixXd Xs = box.rows(Xt);
        const Eigen::VectorXd xs = box(X.row(i).transpose());
        for (size_t k = 0; k < c.qois.size(); ++k) {
            const double truth = c.Q(i, static_cast<Eigen::Index>(k));
            const Eigen::VectorXd yt = without(c.Q.col(static_cast<Eigen::Index>(k)), i);
            const auto kr = surrogates::Kriging::fit(Xs, yt, surrogates::KrigingOptions{});
            auto ws = kr.makeWorkspace();
            const double kq = kr.predictMean(xs.data(), ws);
            row[c.qois[k]] = {{"full", truth},
                              {"from_stored_field", qStored[k]},
                              {"pod_regression", q[k]},
                              {"kriging", kq},
                              {"pod_regression_error", (q[k] - truth) / truth},
                              {"kriging_error", (kq - truth) / truth}};
            regErr[k] += std::abs(q[k] - truth) / std::abs(truth) / static_cast<double>(n);
            krigErr[k] += std::abs(kq - truth) / std::abs(truth) / static_cast<double>(n);
            fieldErr[k] += std::abs(qStored[k] - truth) / std::abs(truth) / static_cast<double>(n);
        }
        rows.push_back(row);
    }
    nlohmann::json summary = nlohmann::json::object();
    for (size_t k = 0; k < c.qois.size(); ++k)
        summary[c.qois[k]] = {{"pod_regression_mean_abs_error", regErr[k]},
                              {"kriging_mean_abs_error", krigErr[k]},
                              {"stored_field_mean_abs_error", fieldErr[k]}};
    return {{"campaign", campaign},
            {"scene", c.scene},
            {"runs", n},
            {"inputs", c.inputs},
            {"cells", c.mesh.cells},
            {"alpha_error_mean", alphaErr},
            {"u_error_mean", c.U.size() > 0 ? nlohmann::json(uErr) : nlohmann::json()},
            {"velocity", c.U.size() > 0 ? "every run" : "not kept by every run (alpha only)"},
            {"predict_seconds", predictSeconds},
            {"summary", summary},
            {"rows", rows}};
}

nlohmann::json campaignRegressionPredict(const fs::path& ledger, const std::string& campaign, const RegressionCheckOptions& o,
                                         const std::map<std::string, double>& point, const fs::path& fieldsFile) {
    const auto c = CampaignFields::load(ledger, campaign);
    Eigen::VectorXd x(c.X.cols());
    for (size_t k = 0; k < c.inputs.size(); ++k) {
        const auto it = point.find(c.inputs[k]);
        if (it == point.end()) throw InputError("at", c.inputs[k] + " missing", "a value for every varying input of the campaign");
        x[static_cast<Eigen::Index>(k)] = it->second;
    }
    for (const auto& [k, v] : point)
        if (std::find(c.inputs.begin(), c.inputs.end(), k) == c.inputs.end())
            throw InputError("at", k, "one of the campaign's varying inputs");
    // The training box: a regression outside it extrapolates, which it says.
    nlohmann::json warnings = nlohmann::json::array();
    for (Eigen::Index k = 0; k < x.size(); ++k) {
        const double lo = c.X.col(k).minCoeff(), hi = c.X.col(k).maxCoeff();
        if (x[k] < lo || x[k] > hi)
            warnings.push_back("outside the training box: " + c.inputs[static_cast<size_t>(k)] + " = " + std::to_string(x[k]) +
                               " (trained on " + std::to_string(lo) + " .. " + std::to_string(hi) + ")");
    }
    const auto reg = PodRegression::fit(c.X, c.F, c.mesh.V, o.modes, o.energy);
    const auto t0 = Clock::now();
    const Eigen::VectorXd alpha = reg.predict(x);
    const auto rhoIt = point.find("rho");
    const double rho = rhoIt != point.end() ? rhoIt->second : c.rho.front();
    const auto q = c.quantities(alpha, rho);
    const double seconds = secondsSince(t0);
    nlohmann::json out{{"campaign", campaign}, {"scene", c.scene}, {"runs", c.X.rows()}, {"modes", reg.modes()},
                       {"predict_seconds", seconds}, {"warnings", warnings}};
    for (size_t k = 0; k < c.inputs.size(); ++k) out["at"][c.inputs[k]] = x[static_cast<Eigen::Index>(k)];
    for (size_t k = 0; k < c.qois.size(); ++k) out[c.qois[k]] = q[k];
    if (!fieldsFile.empty()) {
        std::vector<std::pair<std::string, Eigen::MatrixXd>> fields{{"alpha", alpha}};
        if (c.U.size() > 0) fields.emplace_back("U", PodRegression::fit(c.X, c.U, c.wU, o.modes, o.energy).predict(x));
        store::writeDerivedSnapshots(*c.source, {0.0}, fields,
                                     {{"written_by", "mixload rom regression (POD regression of campaign " + campaign + ")"},
                                      {"at", out["at"].dump()},
                                      {"scene_kind", c.scene},
                                      {"scene_hash", "none (reduced model)"},
                                      {"openfoam_version", "none (reduced model)"}},
                                     fieldsFile);
        out["fields"] = fs::absolute(fieldsFile).string();
        out["fields_written"] = c.U.size() > 0 ? "alpha, U" : "alpha";
    }
    return out;
}

}  // namespace mixload::rom
