// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/regression/campaign_regression.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "common/stats.hpp"
#include "kriging/kriging.hpp"
#include "kriging/unit_box.hpp"
#include "model.hpp"
#include "rom/galerkin/collapse_shape.hpp"
#include "rom/operators/alpha_transport.hpp"
#include "rom/operators/fv_mesh.hpp"
#include "rom/operators/steady_transport.hpp"
#include "rom/regression/pod_regression.hpp"
#include "store/campaign_fields.hpp"
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

template <class T>
std::vector<T> without(const std::vector<T>& v, Eigen::Index i) {
    std::vector<T> out(v);
    if (i >= 0 && static_cast<size_t>(i) < out.size()) out.erase(out.begin() + i);
    return out;
}

// Where the reduced steady model runs: the point's feed and speed (valid: the mixer's zones are known).
struct SteadyPoint {
    bool valid = false;
    double feedKgH = 0, rpm = 0;
};

// A campaign's finished runs with snapshots: their varying inputs X, last stored alpha F (cells x
// runs) and recorded quantities Q, and what reads a quantity from a field.
struct CampaignFields {
    std::vector<store::LedgerRun> runs;
    std::optional<store::SnapshotFile> source;  // the shared mesh and the scene's params
    std::vector<std::string> inputs, qois;
    Eigen::MatrixXd X, F, Q;
    Eigen::MatrixXd U;        // 3 cells x runs: the velocities (NaN columns for runs that kept none)
    std::vector<bool> hasU;   // which runs kept one
    std::vector<Eigen::VectorXd> alphaMean;  // each run's alpha over its final window (empty: not stored)
    Eigen::VectorXd wU;       // their weights: each cell's volume for each component
    std::vector<double> rho;  // mixer: each run's bulk density
    std::vector<surrogates::Point> physical;  // mixer: each run's seven inputs (surrogates' order)
    bool mixer = false;
    int replicates = 0;       // finished replicates left out
    std::string scene;
    FvMesh mesh;
    std::optional<CollapseShape> shape;
    // Mixer: the frozen-rotor zones (empty when no kept file has them), for the reduced steady model.
    std::vector<store::CaseFile::MrfZone> zones;
    nlohmann::json base;  // mixer: the campaign's base scene (what a point's parameters leave alone)

    // minRuns: a training campaign needs three runs and inputs that vary; a hold-out one, a run.
    static CampaignFields load(const fs::path& ledger, const std::string& campaign, const RegressionCheckOptions& o,
                               size_t minRuns = 3) {
        CampaignFields c;
        // A run's own snapshots, or the campaign's kept fields once its directory is gone.
        auto finals = store::campaignFinalFields(ledger, campaign);
        // A replicate (campaign replicate: a design point run again from another deposit) repeats
        // its point's inputs; it measures the label noise and is no training point of its own.
        std::erase_if(finals.runs, [&](const store::FinalField& f) {
            const bool replicate = store::isReplicate(f.run);
            c.replicates += replicate ? 1 : 0;
            return replicate;
        });
        for (const auto& f : finals.runs) c.runs.push_back(f.run);
        if (c.runs.size() < minRuns)
            throw InputError("campaign", campaign,
                             std::to_string(minRuns) + " or more finished runs with snapshots (campaign run --snapshots)");
        for (const auto& [k, v] : c.runs.front().params.items()) {
            if (!v.is_number()) continue;
            bool varies = false;
            for (const auto& r : c.runs) varies = varies || r.params.at(k).get<double>() != v.get<double>();
            if (varies) c.inputs.push_back(k);
        }
        if (c.inputs.empty() && minRuns > 1) throw InputError("campaign", campaign, "a design whose inputs vary");
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
        if (c.mixer) {
            if (!o.mixerInputs) throw std::logic_error("campaign regression: a mixer campaign needs mixerInputs");
            c.base = store::Ledger(ledger).campaign(campaign).value().sceneJson;
        }
        for (Eigen::Index i = 0; i < n; ++i) {
            const auto& f = finals.runs[static_cast<size_t>(i)];
            for (Eigen::Index k = 0; k < d; ++k) c.X(i, k) = f.run.params.at(c.inputs[static_cast<size_t>(k)]).get<double>();
            c.F.col(i) = f.alpha;
            c.alphaMean.push_back(f.alphaWindowMean);
            for (size_t q = 0; q < c.qois.size(); ++q) c.Q(i, static_cast<Eigen::Index>(q)) = f.run.result.at(c.qois[q]).get<double>();
            c.rho.push_back(c.mixer ? f.bulkDensity : 0.0);
            if (c.mixer) c.physical.push_back(o.mixerInputs(c.base, f.run.params));
        }
        if (c.mixer) c.zones = c.source->mrfZones();
        // Runs kept before velocities were (or whose directories were gone by then) have none: the
        // velocity is regressed on the runs that have one.
        c.U = Eigen::MatrixXd::Constant(3 * c.mesh.cells, n, std::nan(""));
        for (Eigen::Index i = 0; i < n; ++i) {
            const auto& u = finals.runs[static_cast<size_t>(i)].U;
            c.hasU.push_back(u.size() == 3 * c.mesh.cells && u.allFinite());
            if (c.hasU.back()) c.U.col(i) = u;
        }
        c.wU = c.mesh.V.replicate(1, 3).transpose().reshaped();
        return c;
    }

    // The reduced steady model: the loading a velocity field holds once the steady powder
    // transport from the inlet has filled it (rom/operators/steady_transport), with the run's
    // feed entering the inlet as powder and the rotor turning at its speed. NaN without MRF zones.
    double steadyLoading(const Eigen::VectorXd& u, double rho, double feedKgH, double rpmValue) const {
        if (!mixer || zones.empty() || !(rho > 0)) return std::nan("");
        const Vectors U = asVectors(u);
        Vectors boundaryU = Vectors::Zero(mesh.boundaryFaces, 3);
        for (const auto& p : mesh.patches) {
            const double area = mesh.magSf.segment(p.start, p.size).sum();
            for (Eigen::Index f = p.start; f < p.start + p.size; ++f) {
                if (p.name == "inlet") boundaryU.row(f - mesh.internalFaces) = -feedKgH / 3600 / rho / area * mesh.Sf.row(f) / mesh.magSf[f];
                else if (p.name == "outlet") boundaryU.row(f - mesh.internalFaces) = U.row(mesh.owner[f]);
            }
        }
        auto turning = zones;
        for (auto& z : turning) z.omega = rpmValue * 2 * M_PI / 60;
        const auto s = steadyPowder(mesh, fluxFromVelocity(mesh, U, boundaryU, turning, "outlet"), {{"inlet", 1.0}});
        return rho * clampFraction(s.alpha).dot(mesh.V);
    }

    // Where run i's reduced steady model runs: its feed and speed,
    // when it kept a velocity and the mixer's zones are known.
    SteadyPoint steadyPoint(size_t i) const {
        if (!mixer || !hasU[i] || zones.empty()) return {};
        return {true, physical[i][surrogates::kFeed], physical[i][surrogates::kRpm]};
    }

    // The inputs, velocities and physical points of the runs that kept a velocity, without run `except`.
    struct VelocityRuns {
        Eigen::MatrixXd X, U;
        std::vector<surrogates::Point> P;
    };
    VelocityRuns velocityTraining(Eigen::Index except = -1) const {
        std::vector<Eigen::Index> keep;
        for (Eigen::Index i = 0; i < X.rows(); ++i)
            if (hasU[static_cast<size_t>(i)] && i != except) keep.push_back(i);
        VelocityRuns v{Eigen::MatrixXd(static_cast<Eigen::Index>(keep.size()), X.cols()),
                       Eigen::MatrixXd(U.rows(), static_cast<Eigen::Index>(keep.size())), {}};
        for (size_t k = 0; k < keep.size(); ++k) {
            v.X.row(static_cast<Eigen::Index>(k)) = X.row(keep[k]);
            v.U.col(static_cast<Eigen::Index>(k)) = U.col(keep[k]);
            if (mixer) v.P.push_back(physical[static_cast<size_t>(keep[k])]);
        }
        return v;
    }

    // What a field says of a run: the instantaneous loading (at bulk density rho) or the
    // deposit's runout and height.
    std::vector<double> quantities(const Eigen::VectorXd& alpha, double bulkDensity) const {
        if (mixer) return {bulkDensity * clampFraction(alpha).dot(mesh.V)};
        return {shape->runoutStar(mesh, alpha), shape->heightStar(mesh, alpha)};
    }
};
}  // namespace

namespace {
// The training runs of one check: inputs, fields and quantities.
struct Training {
    Eigen::MatrixXd X, F, Q;
    std::vector<surrogates::Point> P;  // mixer: their seven inputs
    CampaignFields::VelocityRuns velocity;
};

// A velocity regression needs as many training runs as the alpha regression of a three-run
// leave-one-out.
constexpr Eigen::Index kMinVelocityRuns = 2;

// Running means and maxima over the checked runs.
struct Tally {
    std::vector<double> reg, krig, field, regMax, krigMax;
    std::vector<std::vector<double>> regMinusKrig;  // per quantity, run by run: |error| of the regression minus kriging's
    double alpha = 0, u = 0, seconds = 0;
    double alphaProjected = 0, uProjected = 0;  // the modes' own errors (projection)
    // Runs whose final window's mean field is known: the final field's distance from it (the
    // flow's own fluctuation) and the prediction's.
    double fluctuation = 0, errorToMean = 0;
    int meanRuns = 0;
    int runs = 0, uRuns = 0;
    // The reduced steady model on the predicted and on the run's own velocity.
    double steady = 0, steadyMax = 0, steadyOwn = 0, steadySeconds = 0;
    int steadyRuns = 0;
    explicit Tally(size_t q) : reg(q), krig(q), field(q), regMax(q), krigMax(q), regMinusKrig(q) {}
};

// The models a check fits on its training runs. A mixer campaign with five runs or more: the
// loading model issue 16 ships (`surrogate fit --similarity`: kriging of M/rho in the similarity
// variables, the transforms chosen by leave-one-out), and the POD regression sees the runs in that
// model's own coordinates, so that the two regressions compared see the same inputs. Otherwise:
// plain kriging of each quantity, and both in the design inputs' unit box. Fitted once per training
// set: the leave-one-out check fits one per run, the hold-out check one for all its runs.
struct Fitted {
    std::optional<surrogates::Surrogate> surrogate;
    surrogates::UnitBox box;
    bool logField = false;
    double floor = 0;
    PodRegression alpha;  // of the regressed field (alpha, or ln(alpha + floor))
    std::optional<PodRegression> U;
    std::vector<surrogates::Kriging> kriging;

    Fitted(const CampaignFields& c, const Training& t, const RegressionCheckOptions& o)
        : surrogate(fitSurrogate(c, t, o.surrogateNoise)), box(surrogates::UnitBox::of(t.X)), logField(o.logField), floor(o.logFloor),
          alpha(PodRegression::fit(inputs(t.X, t.P), toRegressed(t.F), c.mesh.V, o.modes, o.energy)) {
        if (t.velocity.U.cols() >= kMinVelocityRuns)
            U = PodRegression::fit(inputs(t.velocity.X, t.velocity.P), t.velocity.U, c.wU, o.modes, o.energy);
        if (surrogate) return;
        const Eigen::MatrixXd Xs = box.rows(t.X);
        for (Eigen::Index k = 0; k < t.Q.cols(); ++k) kriging.push_back(surrogates::Kriging::fit(Xs, t.Q.col(k), surrogates::KrigingOptions{}));
    }

    static std::optional<surrogates::Surrogate> fitSurrogate(const CampaignFields& c, const Training& t, double noise) {
        if (!c.mixer || t.P.size() < 5) return std::nullopt;
        std::vector<surrogates::Row> rows;
        for (size_t i = 0; i < t.P.size(); ++i) rows.push_back({std::to_string(i), t.P[i], t.Q(static_cast<Eigen::Index>(i), 0)});
        surrogates::FitOptions fo;
        fo.similarity = true;
        fo.noise = noise;
        return surrogates::Surrogate::fit(rows, fo, nlohmann::json::object());
    }
    Eigen::MatrixXd toRegressed(const Eigen::MatrixXd& F) const {
        if (!logField) return F;
        return (F.array().max(0.0) + floor).log().matrix();
    }
    // The powder fraction at a run's regression inputs, back in [0, 1].
    Eigen::VectorXd predictAlpha(const Eigen::VectorXd& in) const { return fromRegressed(alpha.predict(in)); }
    // A run's own powder fraction projected on the modes: what the modes themselves miss. Of alpha
    // it bounds the regression's field error from below; of ln alpha it is a projection in the
    // logarithm, near that bound but not one.
    Eigen::VectorXd projectAlpha(const Eigen::VectorXd& alphaRun) const {
        const Eigen::VectorXd r = toRegressed(alphaRun);
        return fromRegressed(alpha.basis().reconstruct(alpha.basis().project(r)));
    }
    Eigen::VectorXd fromRegressed(const Eigen::VectorXd& r) const {
        if (!logField) return r;
        return (r.array().exp() - floor).max(0.0).min(1.0).matrix();
    }
    // A run's inputs as the regressions see them.
    Eigen::VectorXd input(const Eigen::VectorXd& x, const surrogates::Point* p) const {
        if (!surrogate) return x;
        const auto z = surrogate->coordinates(*p);
        return Eigen::Map<const Eigen::VectorXd>(z.data(), static_cast<Eigen::Index>(z.size()));
    }
    Eigen::MatrixXd inputs(const Eigen::MatrixXd& X, const std::vector<surrogates::Point>& P) const {
        if (!surrogate) return X;
        Eigen::MatrixXd Z(static_cast<Eigen::Index>(P.size()), static_cast<Eigen::Index>(surrogate->inputs().size()));
        for (size_t i = 0; i < P.size(); ++i) Z.row(static_cast<Eigen::Index>(i)) = input(Eigen::VectorXd(), &P[i]).transpose();
        return Z;
    }
    // Quantity k at a run by the comparison model.
    double quantity(size_t k, const Eigen::VectorXd& x, const surrogates::Point* p) const {
        if (surrogate) {
            auto ws = surrogate->makeWorkspace();
            return surrogate->predict(*p, ws).m;
        }
        const Eigen::VectorXd xs = box(x);
        auto ws = kriging[k].makeWorkspace();
        return kriging[k].predictMean(xs.data(), ws);
    }
    std::string field() const { return logField ? "ln(alpha + " + std::to_string(floor) + ")" : "alpha"; }
    std::string comparison() const {
        return surrogate ? "the loading surrogate (surrogate fit --similarity): kriging of " + surrogate->transform().describe()
                         : "kriging of each quantity on the design inputs";
    }
};

// One run predicted from the training runs by POD regression (its field, and the quantities read
// from it) and by kriging of the quantities, against the run's own field and recorded quantities.
nlohmann::json checkRun(const CampaignFields& c, const Fitted& fit, const Eigen::VectorXd& x, const surrogates::Point* p,
                        const Eigen::VectorXd& alphaRun, const Eigen::VectorXd& alphaMean, const Eigen::VectorXd& uRun, const Eigen::RowVectorXd& qRun, double rho,
                        const SteadyPoint& steady, Tally& tally) {
    const auto t0 = Clock::now();
    const Eigen::VectorXd in = fit.input(x, p);
    const Eigen::VectorXd alpha = fit.predictAlpha(in);
    const auto q = c.quantities(alpha, rho);
    tally.seconds += secondsSince(t0);
    const auto qStored = c.quantities(alphaRun, rho);
    const auto relativeL2 = [](const Eigen::VectorXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& w) {
        return std::sqrt((a - b).cwiseAbs2().dot(w) / b.cwiseAbs2().dot(w));
    };
    const double aErr = relativeL2(alpha, alphaRun, c.mesh.V);
    const double aProj = relativeL2(fit.projectAlpha(alphaRun), alphaRun, c.mesh.V);
    tally.alpha += aErr;
    tally.alphaProjected += aProj;
    ++tally.runs;
    nlohmann::json row{{"alpha_error", aErr}, {"alpha_projection_error", aProj}, {"modes", fit.alpha.modes()}};
    if (alphaMean.size() == alphaRun.size()) {
        const double fl = relativeL2(alphaRun, alphaMean, c.mesh.V), toMean = relativeL2(alpha, alphaMean, c.mesh.V);
        row["alpha_fluctuation"] = fl;
        row["alpha_error_to_window_mean"] = toMean;
        tally.fluctuation += fl, tally.errorToMean += toMean, ++tally.meanRuns;
    }
    for (size_t k = 0; k < c.inputs.size(); ++k) row[c.inputs[k]] = x[static_cast<Eigen::Index>(k)];
    nlohmann::json steadyRow;
    if (fit.U && uRun.size() > 0) {
        const Eigen::VectorXd u = fit.U->predict(in);
        const double e = relativeL2(u, uRun, c.wU);
        const auto& b = fit.U->basis();
        const double eProj = relativeL2(b.reconstruct(b.project(uRun)), uRun, c.wU);
        row["u_error"] = e;
        row["u_projection_error"] = eProj;
        tally.u += e;
        tally.uProjected += eProj;
        ++tally.uRuns;
        if (steady.valid) {
            const auto t1 = Clock::now();
            const double m = c.steadyLoading(u, rho, steady.feedKgH, steady.rpm);
            tally.steadySeconds += secondsSince(t1);
            const double own = c.steadyLoading(uRun, rho, steady.feedKgH, steady.rpm);
            const double truth = qRun[0];
            steadyRow = {{"steady_model", m},
                         {"steady_model_error", (m - truth) / truth},
                         {"steady_model_on_run_u", own},
                         {"steady_model_on_run_u_error", (own - truth) / truth}};
            tally.steady += std::abs(m - truth) / truth;
            tally.steadyMax = std::max(tally.steadyMax, std::abs(m - truth) / truth);
            tally.steadyOwn += std::abs(own - truth) / truth;
            ++tally.steadyRuns;
        }
    }
    row["kriging_model"] = fit.comparison();
    row["regressed_field"] = fit.field();
    for (size_t k = 0; k < c.qois.size(); ++k) {
        const double truth = qRun[static_cast<Eigen::Index>(k)];
        const double kq = fit.quantity(k, x, p);
        row[c.qois[k]] = {{"full", truth},
                          {"from_stored_field", qStored[k]},
                          {"pod_regression", q[k]},
                          {"kriging", kq},
                          {"pod_regression_error", (q[k] - truth) / truth},
                          {"kriging_error", (kq - truth) / truth}};
        const double er = std::abs(q[k] - truth) / std::abs(truth), ek = std::abs(kq - truth) / std::abs(truth);
        tally.reg[k] += er, tally.krig[k] += ek;
        tally.regMinusKrig[k].push_back(er - ek);
        tally.regMax[k] = std::max(tally.regMax[k], er), tally.krigMax[k] = std::max(tally.krigMax[k], ek);
        tally.field[k] += std::abs(qStored[k] - truth) / std::abs(truth);
    }
    if (!steadyRow.is_null()) row["loading_kg"].update(steadyRow);
    return row;
}

nlohmann::json summarise(const CampaignFields& c, const Tally& t, const RegressionCheckOptions& o) {
    const double n = t.runs;
    nlohmann::json summary = nlohmann::json::object();
    for (size_t k = 0; k < c.qois.size(); ++k)
        summary[c.qois[k]] = {{"pod_regression_mean_abs_error", t.reg[k] / n},
                              {"pod_regression_max_abs_error", t.regMax[k]},
                              {"kriging_mean_abs_error", t.krig[k] / n},
                              {"kriging_max_abs_error", t.krigMax[k]},
                              {"stored_field_mean_abs_error", t.field[k] / n}};
    // Whether the runs can tell the two apart: the paired difference's 90% bootstrap interval.
    for (size_t k = 0; k < c.qois.size(); ++k)
        if (t.regMinusKrig[k].size() >= 2) {
            const auto ci = bootstrapMeanInterval90(t.regMinusKrig[k]);
            summary[c.qois[k]]["pod_minus_kriging_mean_abs_error"] = (t.reg[k] - t.krig[k]) / n;
            summary[c.qois[k]]["pod_minus_kriging_ci90"] = {ci[0], ci[1]};
        }
    if (t.steadyRuns > 0)
        summary["loading_kg"]["steady_model_mean_abs_error"] = t.steady / t.steadyRuns,
        summary["loading_kg"]["steady_model_max_abs_error"] = t.steadyMax,
        summary["loading_kg"]["steady_model_on_run_u_mean_abs_error"] = t.steadyOwn / t.steadyRuns,
        summary["loading_kg"]["steady_model_seconds"] = t.steadySeconds / t.steadyRuns;
    return {{"scene", c.scene},
            {"inputs", c.inputs},
            {"regressed_field", o.logField ? "ln(alpha + " + std::to_string(o.logFloor) + ")" : "alpha"},
            {"replicates_left_out", c.replicates},
            {"cells", c.mesh.cells},
            {"alpha_error_mean", t.alpha / n},
            {"alpha_projection_error_mean", t.alphaProjected / n},
            {"u_error_mean", t.uRuns > 0 ? nlohmann::json(t.u / t.uRuns) : nlohmann::json()},
            {"u_projection_error_mean", t.uRuns > 0 ? nlohmann::json(t.uProjected / t.uRuns) : nlohmann::json()},
            {"alpha_fluctuation_mean", t.meanRuns > 0 ? nlohmann::json(t.fluctuation / t.meanRuns) : nlohmann::json()},
            {"alpha_error_to_window_mean_mean", t.meanRuns > 0 ? nlohmann::json(t.errorToMean / t.meanRuns) : nlohmann::json()},
            {"window_mean_runs", t.meanRuns},
            {"u_error_runs", t.uRuns},
            {"velocity", t.uRuns == 0 ? "fewer than " + std::to_string(kMinVelocityRuns) + " training runs kept one (alpha only)"
                         : t.uRuns == t.runs ? std::string("every run")
                                             : std::to_string(t.uRuns) + " of " + std::to_string(t.runs) + " runs (the others kept none)"},
            {"predict_seconds", t.seconds / n},
            {"summary", summary}};
}
}  // namespace

nlohmann::json campaignRegressionCheck(const fs::path& ledger, const std::string& campaign, const RegressionCheckOptions& o) {
    const auto c = CampaignFields::load(ledger, campaign, o);
    const auto n = c.X.rows();
    Tally tally(c.qois.size());
    nlohmann::json rows = nlohmann::json::array();
    for (Eigen::Index i = 0; i < n; ++i) {
        const auto r = static_cast<size_t>(i);
        Training t{without(c.X, i), without(c.F.transpose(), i).transpose(), without(c.Q, i), without(c.physical, i),
                   c.velocityTraining(i)};
        const bool withU = c.hasU[r];
        auto row = checkRun(c, Fitted(c, t, o), c.X.row(i).transpose(), c.mixer ? &c.physical[r] : nullptr, c.F.col(i), c.alphaMean[r],
                            withU ? Eigen::VectorXd(c.U.col(i)) : Eigen::VectorXd(), c.Q.row(i), c.rho[r],
                            c.steadyPoint(r), tally);
        row["run"] = c.runs[static_cast<size_t>(i)].index;
        rows.push_back(row);
    }
    auto out = summarise(c, tally, o);
    out["campaign"] = campaign;
    out["runs"] = n;
    out["rows"] = rows;
    return out;
}

nlohmann::json campaignRegressionHoldout(const fs::path& ledger, const std::string& campaign, const fs::path& holdoutLedger,
                                         const std::string& holdout, const RegressionCheckOptions& o) {
    return campaignRegressionHoldouts(ledger, campaign, holdoutLedger, holdout, {o}).front();
}

std::vector<nlohmann::json> campaignRegressionHoldouts(const fs::path& ledger, const std::string& campaign,
                                                       const fs::path& holdoutLedger, const std::string& holdout,
                                                       const std::vector<RegressionCheckOptions>& variants) {
    if (variants.empty()) throw std::logic_error("campaign regression: no regression asked for");
    const auto t0 = Clock::now();
    const auto c = CampaignFields::load(ledger, campaign, variants.front());
    const auto h = CampaignFields::load(holdoutLedger, holdout, variants.front(), 1);
    const double loadSeconds = secondsSince(t0);
    if (h.source->meshFingerprint() != c.source->meshFingerprint())
        throw InputError("holdout", holdout, "a campaign on the training campaign's mesh (" + campaign + ")");
    if (h.scene != c.scene) throw InputError("holdout", holdout, "a campaign of the training campaign's scene (" + c.scene + ")");
    // The hold-out runs' values of the training design's inputs (the hold-out may hold some fixed),
    // and which lie outside the training box.
    Eigen::MatrixXd X(static_cast<Eigen::Index>(h.runs.size()), c.X.cols());
    nlohmann::json outside = nlohmann::json::array();
    for (size_t j = 0; j < h.runs.size(); ++j) {
        const auto r = static_cast<Eigen::Index>(j);
        bool inside = true;
        for (size_t k = 0; k < c.inputs.size(); ++k) {
            const auto& p = h.runs[j].params;
            if (!p.contains(c.inputs[k]) || !p[c.inputs[k]].is_number())
                throw InputError("holdout", holdout, "runs that give every input the training campaign varies (" + c.inputs[k] + ")");
            const auto col = static_cast<Eigen::Index>(k);
            X(r, col) = p[c.inputs[k]].get<double>();
            inside = inside && X(r, col) >= c.X.col(col).minCoeff() && X(r, col) <= c.X.col(col).maxCoeff();
        }
        if (!inside) outside.push_back(h.runs[j].index);
    }
    std::vector<nlohmann::json> results;
    for (const auto& o : variants) {
        const auto t1 = Clock::now();
        const Fitted fit(c, Training{c.X, c.F, c.Q, c.physical, c.velocityTraining()}, o);
        const double fitSeconds = secondsSince(t1);
        Tally tally(c.qois.size());
        nlohmann::json rows = nlohmann::json::array();
        for (size_t j = 0; j < h.runs.size(); ++j) {
            const auto i = static_cast<Eigen::Index>(j);
            const bool withU = h.hasU[j];
            auto row = checkRun(c, fit, X.row(i).transpose(), c.mixer ? &h.physical[j] : nullptr, h.F.col(i), h.alphaMean[j],
                                withU ? Eigen::VectorXd(h.U.col(i)) : Eigen::VectorXd(), h.Q.row(i), h.rho[j],
                                h.steadyPoint(j), tally);
            row["run"] = h.runs[j].index;
            rows.push_back(row);
        }
        auto out = summarise(c, tally, o);
        out["campaign"] = campaign;
        out["holdout"] = holdout;
        out["runs"] = c.X.rows();
        out["holdout_runs"] = h.runs.size();
        out["holdout_outside_training_box"] = outside;
        out["load_seconds"] = loadSeconds;
        out["fit_seconds"] = fitSeconds;
        out["rows"] = rows;
        results.push_back(std::move(out));
    }
    return results;
}

nlohmann::json campaignRegressionPredict(const fs::path& ledger, const std::string& campaign, const RegressionCheckOptions& o,
                                         const std::map<std::string, double>& point, const fs::path& fieldsFile) {
    const auto c = CampaignFields::load(ledger, campaign, o);
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
    const Fitted fit(c, Training{c.X, c.F, c.Q, c.physical, c.velocityTraining()}, o);
    const surrogates::Point p = c.mixer ? o.mixerInputs(c.base, nlohmann::json(point)) : surrogates::Point{};
    const double rho = c.mixer ? p[surrogates::kRho] : c.rho.front();
    const auto t0 = Clock::now();
    const Eigen::VectorXd in = fit.input(x, &p);
    const Eigen::VectorXd alpha = fit.predictAlpha(in);
    const auto q = c.quantities(alpha, rho);
    const double seconds = secondsSince(t0);
    nlohmann::json out{{"campaign", campaign}, {"scene", c.scene}, {"runs", c.X.rows()}, {"modes", fit.alpha.modes()},
                       {"predict_seconds", seconds}, {"warnings", warnings}, {"kriging_model", fit.comparison()},
                       {"regressed_field", fit.field()}};
    for (size_t k = 0; k < c.inputs.size(); ++k) out["at"][c.inputs[k]] = x[static_cast<Eigen::Index>(k)];
    for (size_t k = 0; k < c.qois.size(); ++k) {
        out[c.qois[k]] = q[k];
        out["kriging"][c.qois[k]] = fit.quantity(k, x, &p);
    }
    if (!fieldsFile.empty()) {
        std::vector<std::pair<std::string, Eigen::MatrixXd>> fields{{"alpha", alpha}};
        if (fit.U) fields.emplace_back("U", fit.U->predict(in));
        store::writeDerivedSnapshots(*c.source, {0.0}, fields,
                                     {{"written_by", "mixload rom regression (POD regression of campaign " + campaign + ")"},
                                      {"at", out["at"].dump()},
                                      {"scene_kind", c.scene},
                                      {"scene_hash", "none (reduced model)"},
                                      {"openfoam_version", "none (reduced model)"}},
                                     fieldsFile);
        out["fields"] = fs::absolute(fieldsFile).string();
        out["fields_written"] = fields.size() > 1 ? "alpha, U" : "alpha";
    }
    return out;
}

}  // namespace mixload::rom
