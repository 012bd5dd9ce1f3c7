// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/regression/campaign_regression.hpp"

#include <chrono>
#include <cmath>

#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "kriging/kriging.hpp"
#include "rom/operators/alpha_transport.hpp"
#include "rom/galerkin/collapse_shape.hpp"
#include "rom/operators/fv_mesh.hpp"
#include "rom/regression/pod_regression.hpp"
#include "store/ledger.hpp"
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
}  // namespace

nlohmann::json campaignRegressionCheck(const fs::path& ledger, const std::string& campaign, const RegressionCheckOptions& o) {
    if (!fs::exists(ledger)) throw InputError("dir", ledger.parent_path().string(), "a campaign directory with a ledger.sqlite");
    const store::Ledger l(ledger);
    if (!l.campaign(campaign)) throw InputError("campaign", campaign, "a campaign of " + ledger.string());
    std::vector<store::LedgerRun> runs;
    for (auto& r : l.runs(campaign))
        if (r.status == "done" && fs::exists(fs::path(r.runDir) / "snapshots.h5")) runs.push_back(r);
    if (runs.size() < 3)
        throw InputError("campaign", campaign, "three or more finished runs with snapshots (campaign run --snapshots)");

    // Inputs: the design's parameters that vary.
    std::vector<std::string> inputs;
    for (const auto& [k, v] : runs.front().params.items()) {
        if (!v.is_number()) continue;
        bool varies = false;
        for (const auto& r : runs) varies = varies || r.params.at(k).get<double>() != v.get<double>();
        if (varies) inputs.push_back(k);
    }
    if (inputs.empty()) throw InputError("campaign", campaign, "a design whose inputs vary");
    const auto n = static_cast<Eigen::Index>(runs.size());
    const auto d = static_cast<Eigen::Index>(inputs.size());

    std::vector<store::SnapshotFile> files;
    for (const auto& r : runs) files.emplace_back(fs::path(r.runDir) / "snapshots.h5");
    for (const auto& f : files)
        if (f.meshFingerprint() != files.front().meshFingerprint())
            throw InputError("campaign", campaign, "runs on one mesh (" + f.path().string() + " differs)");
    const std::string scene = files.front().params().value("scene", std::string());
    const bool mixer = scene == "mixer3d";
    if (!mixer && scene != "collapse2d") throw InputError("scene", scene, "mixer3d or collapse2d runs");
    const Eigen::VectorXd V = files.front().cellVolumes();
    const FvMesh mesh = FvMesh::fromCase(files.front());
    std::optional<CollapseShape> shape;
    if (!mixer) shape = CollapseShape::fromCase(files.front());

    Eigen::MatrixXd X(n, d), F(static_cast<Eigen::Index>(files.front().cells()), n);
    std::vector<std::string> qois = mixer ? std::vector<std::string>{"loading_kg"} : std::vector<std::string>{"runout_star", "height_star"};
    Eigen::MatrixXd Q(n, static_cast<Eigen::Index>(qois.size()));
    std::vector<double> rho(static_cast<size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i) {
        const auto& r = runs[static_cast<size_t>(i)];
        for (Eigen::Index k = 0; k < d; ++k) X(i, k) = r.params.at(inputs[static_cast<size_t>(k)]).get<double>();
        const auto& f = files[static_cast<size_t>(i)];
        F.col(i) = f.column("alpha", f.times().size() - 1);
        for (size_t q = 0; q < qois.size(); ++q) Q(i, static_cast<Eigen::Index>(q)) = r.result.at(qois[q]).get<double>();
        if (mixer) rho[static_cast<size_t>(i)] = f.params().at("material.bulk_density_kg_m3").get<double>();
    }
    // What the field says of the run: the instantaneous loading or the deposit's runout and height.
    const auto quantities = [&](const Eigen::VectorXd& alpha, size_t i) {
        if (mixer) return std::vector<double>{rho[i] * clampFraction(alpha).dot(V)};
        return std::vector<double>{shape->runoutStar(mesh, alpha), shape->heightStar(mesh, alpha)};
    };

    nlohmann::json rows = nlohmann::json::array();
    std::vector<double> regErr(qois.size(), 0), krigErr(qois.size(), 0), fieldErr(qois.size(), 0);
    double alphaErr = 0, predictSeconds = 0;
    const Eigen::VectorXd lo = X.colwise().minCoeff().transpose(), span = (X.colwise().maxCoeff().transpose() - lo).cwiseMax(1e-12);
    for (Eigen::Index i = 0; i < n; ++i) {
        const Eigen::MatrixXd Xt = without(X, i);
        const Eigen::MatrixXd Ft = without(F.transpose(), i).transpose();
        const auto reg = PodRegression::fit(Xt, Ft, V, o.modes, o.energy);
        const auto t0 = Clock::now();
        const Eigen::VectorXd alpha = reg.predict(X.row(i).transpose());
        const auto q = quantities(alpha, static_cast<size_t>(i));
        predictSeconds += secondsSince(t0) / static_cast<double>(n);
        const auto qStored = quantities(F.col(i), static_cast<size_t>(i));
        const double aErr = std::sqrt((alpha - F.col(i)).cwiseAbs2().dot(V) / F.col(i).cwiseAbs2().dot(V));
        alphaErr += aErr / static_cast<double>(n);
        nlohmann::json row{{"run", runs[static_cast<size_t>(i)].index}, {"alpha_error", aErr}, {"modes", reg.modes()}};
        for (Eigen::Index k = 0; k < d; ++k) row[inputs[static_cast<size_t>(k)]] = X(i, k);
        Eigen::MatrixXd Xs(n - 1, d);
        for (Eigen::Index j = 0; j < n - 1; ++j) Xs.row(j) = (Xt.row(j).transpose() - lo).cwiseQuotient(span).transpose();
        const Eigen::VectorXd xs = (X.row(i).transpose() - lo).cwiseQuotient(span);
        for (size_t k = 0; k < qois.size(); ++k) {
            const double truth = Q(i, static_cast<Eigen::Index>(k));
            const Eigen::VectorXd yt = without(Q.col(static_cast<Eigen::Index>(k)), i);
            const auto kr = surrogates::Kriging::fit(Xs, yt, surrogates::KrigingOptions{});
            auto ws = kr.makeWorkspace();
            const double kq = kr.predictMean(xs.data(), ws);
            row[qois[k]] = {{"full", truth},
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
    for (size_t k = 0; k < qois.size(); ++k)
        summary[qois[k]] = {{"pod_regression_mean_abs_error", regErr[k]},
                            {"kriging_mean_abs_error", krigErr[k]},
                            {"stored_field_mean_abs_error", fieldErr[k]}};
    return {{"campaign", campaign},
            {"scene", scene},
            {"runs", n},
            {"inputs", inputs},
            {"cells", files.front().cells()},
            {"alpha_error_mean", alphaErr},
            {"predict_seconds", predictSeconds},
            {"summary", summary},
            {"rows", rows}};
}

}  // namespace mixload::rom
