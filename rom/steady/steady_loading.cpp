// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/steady/steady_loading.hpp"

#include <chrono>

#include "common/input_error.hpp"
#include "rom/operators/alpha_transport.hpp"
#include "rom/operators/steady_transport.hpp"

namespace mixload::rom {

nlohmann::json steadyLoadingCheck(const store::SnapshotFile& f, const SteadyCheckOptions& o) {
    const int every = o.every;
    if (every < 1) throw InputError("--every", std::to_string(every), "1 or more");
    if (o.meanLast < 0) throw InputError("--mean-last", std::to_string(o.meanLast), "0 (none) or more");
    if (!(o.marchSeconds >= 0)) throw InputError("--march", std::to_string(o.marchSeconds), "0 (none) or more seconds");
    if (!(o.cAlpha >= 0)) throw InputError("--c-alpha", std::to_string(o.cAlpha), "0 or more");
    const auto params = f.params();
    if (params.value("scene", std::string()) != "mixer3d")
        throw InputError("snapshots", f.path().string(), "a mixer run's snapshots");
    const double rho = params.value("material.bulk_density_kg_m3", 0.0);
    const auto fields = f.fields();
    const bool hasPhi = f.hasFaceField("phi");
    bool hasU = std::find(fields.begin(), fields.end(), "U") != fields.end() && f.schemaVersion() >= 2;
    const auto zones = f.mrfZones();
    // A frozen-rotor run whose file predates the kept zones cannot have its flux rebuilt.
    const bool mrf = params.value("method", std::string()) == "mrf";
    if (mrf && zones.empty()) hasU = false;
    if (!hasPhi && !hasU)
        throw InputError("snapshots", f.path().string(),
                         "phi (snapshots export --fields alpha,U,phi) or U with the MRF zones (files written since they are kept)");
    const FvMesh m = FvMesh::fromCase(f);
    const std::map<std::string, double> inlet{{"inlet", 1.0}};
    const auto mass = [&](const Eigen::VectorXd& a) { return rho * clampFraction(a).dot(m.V); };

    nlohmann::json rows = nlohmann::json::array();
    const auto& times = f.times();
    double seconds = 0;
    int solves = 0;
    for (size_t k = 0; k < times.size(); ++k) {
        if (k % static_cast<size_t>(every) != 0 && k + 1 != times.size()) continue;
        nlohmann::json row{{"time_s", times[k]}, {"loading_kg", mass(f.column("alpha", k))}};
        Eigen::VectorXd phi;
        if (hasPhi) {
            phi = f.faceColumn("phi", k);
            const auto t0 = std::chrono::steady_clock::now();
            const auto s = steadyPowder(m, phi, inlet);
            seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            ++solves;
            row["steady_from_phi_kg"] = mass(s.alpha);
            row["powder_balance_phi"] = (s.outflow - s.inflow) / s.inflow;
        }
        if (hasU) {
            const Eigen::VectorXd u = f.column("U", k), ub = f.boundaryColumn("U", k);
            const Eigen::VectorXd rebuilt = fluxFromVelocity(m, asVectors(u), asVectors(ub), zones, "outlet");
            const auto s = steadyPowder(m, rebuilt, inlet);
            row["steady_from_u_kg"] = mass(s.alpha);
            row["powder_balance_u"] = (s.outflow - s.inflow) / s.inflow;
            if (hasPhi) {
                const auto in = m.internalFaces;
                row["flux_error_u"] = (rebuilt.head(in) - phi.head(in)).norm() / phi.head(in).norm();
            }
        }
        rows.push_back(row);
    }
    nlohmann::json out{{"file", f.path().string()},
            {"cells", m.cells},
            {"bulk_density_kg_m3", rho},
            {"mrf_zones", zones.size()},
            {"from_phi", hasPhi},
            {"from_u", hasU},
            {"seconds_per_steady_solve", solves ? seconds / solves : 0.0},
            {"times", rows}};

    // The flux averaged over the last stored times (a run's flow at its steady state, without its
    // fluctuations), then the march on it.
    const int k = std::min<int>(o.meanLast > 0 ? o.meanLast : (o.marchSeconds > 0 ? 1 : 0), static_cast<int>(times.size()));
    if (k == 0) return out;
    if (!hasPhi) throw InputError("snapshots", f.path().string(), "phi for --mean-last and --march (snapshots export --fields alpha,U,phi)");
    Eigen::VectorXd phi = Eigen::VectorXd::Zero(m.faces());
    double held = 0;
    for (size_t i = times.size() - static_cast<size_t>(k); i < times.size(); ++i) {
        phi += f.faceColumn("phi", i) / k;
        held += mass(f.column("alpha", i)) / k;
    }
    out["mean_flux"] = {{"times", k},
                        {"from_s", times[times.size() - static_cast<size_t>(k)]},
                        {"to_s", times.back()},
                        {"loading_kg", held},
                        {"steady_kg", mass(steadyPowder(m, phi, inlet).alpha)}};
    if (o.marchSeconds > 0) {
        const auto t0 = std::chrono::steady_clock::now();
        const Eigen::VectorXd inflow = patchValues(m, inlet);
        const double dt = transportStep(m, phi, 0.5);
        Eigen::VectorXd alpha = f.column("alpha", times.size() - 1);
        nlohmann::json history = nlohmann::json::array({{{"time_s", 0.0}, {"loading_kg", mass(alpha)}}});
        double t = 0, next = o.marchSeconds / 10;
        long steps = 0;
        while (t < o.marchSeconds) {
            alpha = advanceAlpha(m, alpha, phi, dt, inflow, o.cAlpha);
            t += dt, ++steps;
            if (t >= next - 0.5 * dt) history.push_back({{"time_s", t}, {"loading_kg", mass(alpha)}}), next += o.marchSeconds / 10;
        }
        out["march"] = {{"c_alpha", o.cAlpha},
                        {"step_s", dt},
                        {"steps", steps},
                        {"wall_seconds", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count()},
                        {"history", history}};
    }
    return out;
}

}  // namespace mixload::rom
