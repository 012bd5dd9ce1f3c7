// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/galerkin/collapse_check.hpp"

#include <algorithm>
#include <cmath>

#include "common/input_error.hpp"
#include "model.hpp"
#include "rom/galerkin/collapse_flow.hpp"
#include "rom/operators/alpha_transport.hpp"
#include "rom/operators/fv_operators.hpp"

namespace mixload::rom {

namespace fs = std::filesystem;

namespace {
// A hyper-reduced model's projected convection and viscous terms against the same terms on the whole
// mesh, for the model's own state at each output time (relative error). Computed after the run, so
// that the model's online time does not include this check's whole-mesh evaluations.
std::vector<double> hyperTermErrors(const CollapseGalerkin& rom, const CollapseTrajectory& tr) {
    std::vector<double> out;
    if (!rom.hyper) return out;
    const CollapseFlow model(rom);
    for (size_t i = 0; i < tr.times.size(); ++i) {
        Frozen z = model.freeze(tr.alpha[i]);
        model.setPressure(z, tr.pressure[i]);
        const Eigen::VectorXd& a = tr.flow[i];
        const Eigen::VectorXd mesh = rom.flow.modes.transpose() * model.faceForce(z, a);
        out.push_back(mesh.norm() > 0 ? (model.projectedForce(z, a) - mesh).norm() / mesh.norm() : 0.0);
    }
    return out;
}

// The hyper-reduced terms: how they were built, their error on the training snapshots, and (for a
// check) their error along the model's own trajectory (mean and max over outputs).
nlohmann::json hyperSummary(const CollapseGalerkin& rom, const std::vector<double>& termError) {
    if (!rom.hyper) return {{"hyper", "none"}};
    nlohmann::json out = {{"hyper", rom.hyper->method == HyperMethod::deim ? "deim" : "ecsw"},
                          {"hyper_points", rom.hyper->size()},
                          {"hyper_training_error", rom.hyper->trainingError},
                          {"hyper_convection_points", rom.convectionHyper ? rom.convectionHyper->size() : 0},
                          {"hyper_convection_training_error",
                           rom.convectionHyper ? nlohmann::json(rom.convectionHyper->trainingError) : nlohmann::json()}};
    if (!termError.empty()) {
        double mean = 0, worst = 0;
        for (const double e : termError) mean += e / static_cast<double>(termError.size()), worst = std::max(worst, e);
        out["hyper_term_error_mean"] = mean;
        out["hyper_term_error_max"] = worst;
    }
    return out;
}

double weightedNorm(const Eigen::VectorXd& x, const Eigen::VectorXd& w) { return std::sqrt(x.cwiseAbs2().dot(w)); }
}  // namespace

nlohmann::json checkCollapse(const CollapseGalerkin& built, const store::SnapshotFile& f) {
    if (f.meshFingerprint() != built.meshFingerprint)
        throw InputError("check file", f.path().string(), "a run on the model's mesh");
    // The target's own law (its mu_s, mu_d, I0 and cap): the model's parameters enter here only.
    CollapseGalerkin rom = built;
    rom.law = GranularLaw::fromCase(f);
    const auto& options = rom.options;
    const auto& m = rom.mesh;
    const auto& times = f.times();
    const Eigen::VectorXd wU = m.V.replicate(1, 3).transpose().reshaped();  // per component of a cell
    bool trainedOn = false;
    for (const auto& t : rom.trainFiles) trainedOn = trainedOn || fs::absolute(t) == fs::absolute(f.path());

    // Linear in time between stored times (the diagnoses).
    const auto storedAt = [&](auto column) {
        return [&f, &times, column](double t) {
            const auto hi = std::min<size_t>(std::upper_bound(times.begin(), times.end(), t) - times.begin(), times.size() - 1);
            const size_t lo = hi == 0 ? 0 : hi - 1;
            const double w = hi == lo ? 0 : std::clamp((t - times[lo]) / (times[hi] - times[lo]), 0.0, 1.0);
            return Eigen::VectorXd((1 - w) * column(f, lo) + w * column(f, hi));
        };
    };
    StoredFields stored;
    if (options.storedPressure)
        stored.pressure = storedAt([](const store::SnapshotFile& s, size_t i) { return s.column("p", i); });
    if (options.storedFlux)
        stored.flux = storedAt([](const store::SnapshotFile& s, size_t i) { return s.faceColumn("phi", i); });
    // From rest at t = 0, the column as the case sets it up: nothing of the run is used.
    const CollapseTrajectory tr =
        runCollapseGalerkin(rom, rom.shape.initialAlpha(m), Eigen::VectorXd::Zero(m.faces()), 0.0, times, stored);

    // Every stored time read once: the model against it, the stored fields' own projections on the
    // bases (the lower bounds), and the lithostatic closure on the stored fields (against the
    // solver's p, in the powder, and what it does to the mu(I) viscosity there). U errors are
    // relative to the run's peak |U|, known only after the last time.
    const ColumnPressure lith(m, rom.gravity);
    std::vector<double> uErr(times.size()), uProj(times.size());
    double peakU = 0;
    nlohmann::json rows = nlohmann::json::array();
    double aSum = 0, aMax = 0, aProjSum = 0, pModel = 0, pLith = 0, nuLith = 0;
    for (size_t i = 0; i < times.size(); ++i) {
        const Eigen::VectorXd as = f.column("alpha", i), p = f.column("p", i), Us = f.column("U", i);
        const Eigen::VectorXd al = clampFraction(as), w = al.cwiseProduct(m.V);
        const Eigen::VectorXd rho = (rom.airRho + (rom.law.rho - rom.airRho) * al.array()).matrix();
        const Eigen::VectorXd pl = lith(rho);
        const double pLithAt = weightedNorm(pl - p, w) / weightedNorm(p, w);
        const Eigen::VectorXd sr = strainRate(m, asVectors(Us), asVectors(f.boundaryColumn("U", i)));
        nuLith += weightedNorm(rom.law.nu(sr, pl) - rom.law.nu(sr, p), w) / weightedNorm(rom.law.nu(sr, p), w);
        const double pModelAt = weightedNorm(tr.pressure[i] - p, w) / weightedNorm(p, w);

        const Eigen::VectorXd& ar = tr.alpha[i];
        const double aErr = weightedNorm(ar - as, m.V) / weightedNorm(as, m.V);
        peakU = std::max(peakU, weightedNorm(Us, wU));
        uErr[i] = weightedNorm(rom.cellU * tr.flow[i] - Us, wU);
        const Eigen::VectorXd aProj = rom.flow.project(f.faceColumn("phi", i).cwiseQuotient(m.magSf));
        uProj[i] = weightedNorm(rom.cellU * aProj - Us, wU);
        double alphaProj = 0;
        if (rom.alpha)
            alphaProj = weightedNorm(rom.alphaLift + rom.alpha->reconstruct(rom.alpha->project(as - rom.alphaLift)) - as, m.V) /
                        weightedNorm(as, m.V);
        rows.push_back({{"t", times[i]},
                        {"trained", trainedOn && i % static_cast<size_t>(options.trainEvery) == 0},
                        {"alpha_error", aErr},
                        {"alpha_projection_error", alphaProj},
                        {"runout_star", rom.shape.runoutStar(m, ar)},
                        {"runout_star_full", rom.shape.runoutStar(m, as)},
                        {"height_star", rom.shape.heightStar(m, ar)},
                        {"height_star_full", rom.shape.heightStar(m, as)},
                        {"pressure_error", pModelAt},
                        {"lithostatic_pressure_error", pLithAt},
                        {"kinetic_energy_j", tr.kineticEnergy[i]},
                        {"powder_volume_m3", tr.powderVolume[i]}});
        aSum += aErr;
        aMax = std::max(aMax, aErr);
        aProjSum += alphaProj;
        pModel += pModelAt;
        pLith += pLithAt;
    }
    double uSum = 0, uMax = 0, uProjSum = 0, aHold = 0, uHold = 0;
    int held = 0;
    for (size_t i = 0; i < times.size(); ++i) {
        auto& row = rows[i];
        row["u_error"] = uErr[i] / peakU;
        row["u_projection_error"] = uProj[i] / peakU;
        uSum += uErr[i] / peakU;
        uMax = std::max(uMax, uErr[i] / peakU);
        uProjSum += uProj[i] / peakU;
        if (!row["trained"].get<bool>()) {
            aHold += row["alpha_error"].get<double>();
            uHold += uErr[i] / peakU;
            ++held;
        }
    }
    const std::vector<double> termError = hyperTermErrors(rom, tr);
    for (size_t i = 0; i < termError.size(); ++i) rows[i]["hyper_term_error"] = termError[i];
    const auto& last = rows.back();
    const double n = static_cast<double>(rows.size());
    const double Lr = last["runout_star"], Lf = last["runout_star_full"], Hr = last["height_star"],
                 Hf = last["height_star_full"];
    nlohmann::json out = {{"snapshots", f.path().string()},
            {"trained_on_this_run", trainedOn},
            {"mu_s", rom.law.law.muS},
            {"mu_d", rom.law.law.muD},
            {"i0", rom.law.law.I0},
            {"cells", m.cells},
            {"stored_times", times.size()},
            {"train_files", rom.trainFiles.size()},
            {"train_times", rom.trainTimes},
            {"modes", rom.modes()},
            {"flow_energy_kept", rom.flow.keptEnergy()},
            {"alpha", rom.alpha ? "reduced" : "mesh"},
            {"alpha_modes", rom.alpha ? rom.alpha->modes.cols() : 0},
            {"pressure", options.storedPressure ? "stored (diagnosis)"
                         : options.pressure == PressureClosure::recovered ? "recovered" : "lithostatic"},
            {"flux", options.storedFlux ? "stored (diagnosis)" : "reduced"},
            {"pressure_error_mean", pModel / n},
            {"lithostatic_pressure_error", pLith / n},
            {"lithostatic_viscosity_error", nuLith / n},
            {"alpha_error_mean", aSum / n},
            {"alpha_error_max", aMax},
            {"alpha_projection_error_mean", aProjSum / n},
            {"u_error_mean", uSum / n},
            {"u_error_max", uMax},
            {"u_projection_error_mean", uProjSum / n},
            {"alpha_error_held_out_mean", held ? aHold / held : 0.0},
            {"u_error_held_out_mean", held ? uHold / held : 0.0},
            {"runout_star", Lr},
            {"runout_star_full", Lf},
            {"runout_error", (Lr - Lf) / Lf},
            {"height_star", Hr},
            {"height_star_full", Hf},
            {"height_error", (Hr - Hf) / Hf},
            {"clipped_volume_share", tr.clippedVolume / tr.powderVolume.front()},
            {"steps", tr.steps},
            {"ode_steps", tr.odeSteps},
            {"rhs_evaluations", tr.rhsEvaluations},
            {"jacobian_evaluations", tr.jacobianEvaluations},
            {"build_seconds", rom.buildSeconds},
            {"online_seconds", tr.wallSeconds},
            {"times", rows}};
    out.update(hyperSummary(rom, termError));
    return out;
}

void requireNearTraining(const CollapseGalerkin& rom, double muS, double muD, double i0) {
    const std::pair<const char*, double> asked[] = {{"mu_s", muS}, {"mu_d", muD}, {"i0", i0}};
    for (const auto& [key, v] : asked) {
        double lo = HUGE_VAL, hi = -HUGE_VAL;
        for (const auto& s : rom.sources) {
            const double x = s.value(key, NAN);
            if (std::isnan(x)) continue;
            lo = std::min(lo, x), hi = std::max(hi, x);
        }
        if (!(hi >= lo)) continue;  // a model file without its sources' coefficients
        const double margin = std::max(surrogates::kMaxExtrapolation * (hi - lo), 0.05 * std::max(std::abs(lo), std::abs(hi)));
        if (v < lo - margin || v > hi + margin) {
            std::string flag = key;
            std::replace(flag.begin(), flag.end(), '_', '-');
            throw InputError(flag, formatNumber(v),
                             "within " + formatNumber(lo - margin) + " .. " + formatNumber(hi + margin) +
                                 " (the model's training runs span " + formatNumber(lo) + " .. " + formatNumber(hi) +
                                 "; a quarter of that range, at least 5%, beyond it); run the full model there, or "
                                 "pass --extrapolate");
        }
    }
}

nlohmann::json predictCollapse(const CollapseGalerkin& built, double muS, double muD, double i0, double endTstar,
                               int perTstar, CollapseTrajectory* trajectory) {
    if (!(muS > 0)) throw InputError("mu-s", std::to_string(muS), "> 0");
    if (!(muD > muS)) throw InputError("mu-d", std::to_string(muD), "> mu_s (" + std::to_string(muS) + ")");
    if (!(i0 > 0)) throw InputError("i0", std::to_string(i0), "> 0");
    if (!(endTstar > 0 && endTstar <= 100)) throw InputError("end-tstar", std::to_string(endTstar), "(0, 100]");
    if (perTstar < 1 || perTstar > 1000) throw InputError("writes-per-tstar", std::to_string(perTstar), "1 to 1000");
    CollapseGalerkin rom = built;
    rom.law.law = {muS, muD, i0};
    std::vector<double> outputs;
    for (int k = 1; k <= static_cast<int>(std::ceil(endTstar * perTstar - 1e-9)); ++k)
        outputs.push_back(std::min(endTstar, static_cast<double>(k) / perTstar) * rom.tStar);
    const auto& m = rom.mesh;
    const auto tr = runCollapseGalerkin(rom, rom.shape.initialAlpha(m), Eigen::VectorXd::Zero(m.faces()), 0.0, outputs);
    nlohmann::json hist = nlohmann::json::array();
    for (size_t i = 0; i < tr.times.size(); ++i)
        hist.push_back({{"t_tstar", tr.times[i] / rom.tStar},
                        {"runout_star", rom.shape.runoutStar(m, tr.alpha[i])},
                        {"height_star", rom.shape.heightStar(m, tr.alpha[i])},
                        {"kinetic_energy_j", tr.kineticEnergy[i]}});
    if (trajectory) *trajectory = tr;
    nlohmann::json out = {{"mu_s", muS},
            {"mu_d", muD},
            {"i0", i0},
            {"t_star", rom.tStar},
            {"end_tstar", endTstar},
            {"runout_star", hist.back()["runout_star"]},
            {"height_star", hist.back()["height_star"]},
            {"powder_volume_change", tr.powderVolume.back() / rom.shape.initialAlpha(m).dot(m.V) - 1},
            {"steps", tr.steps},
            {"rhs_evaluations", tr.rhsEvaluations},
            {"online_seconds", tr.wallSeconds},
            {"history", hist}};
    out.update(hyperSummary(rom, {}));
    return out;
}

}  // namespace mixload::rom
