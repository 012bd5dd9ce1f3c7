// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/hyper/viscosity_deim.hpp"

#include <algorithm>
#include <cmath>

#include "common/input_error.hpp"
#include "rom/hyper/deim.hpp"
#include "rom/operators/fv_operators.hpp"
#include "rom/operators/granular_viscosity.hpp"
#include "rom/pod/pod.hpp"

namespace mixload::rom {

nlohmann::json viscosityDeim(const store::SnapshotSet& set, const ViscosityDeimOptions& o) {
    requireRange("modes", o.modes, 1, 10000);
    const auto& first = set.files().front();
    const auto mesh = FvMesh::fromCase(first);
    const auto law = GranularLaw::fromCase(first);
    // Every snapshot's viscosity; even positions (over the whole set) train, odd ones are held out.
    std::vector<Eigen::VectorXd> train, test;
    std::vector<double> trainTimes, testTimes;
    size_t k = 0;
    for (const auto& f : set.files())
        for (size_t t = 0; t < f.times().size(); ++t, ++k) {
            const Eigen::VectorXd sr = strainRate(mesh, asVectors(f.column("U", t)), asVectors(f.boundaryColumn("U", t)));
            Eigen::VectorXd nu = law.nu(sr, f.column("p", t));
            (k % 2 == 0 ? train : test).push_back(nu);
            (k % 2 == 0 ? trainTimes : testTimes).push_back(f.times()[t]);
        }
    if (train.size() < 2) throw InputError("snapshots", std::to_string(k), "at least 2 stored times (4 for a hold-out)");
    const auto transform = [&](const Eigen::VectorXd& nu) { return o.logSpace ? Eigen::VectorXd(nu.array().log()) : nu; };
    const auto back = [&](const Eigen::VectorXd& v) { return o.logSpace ? Eigen::VectorXd(v.array().exp()) : v; };
    Eigen::MatrixXd x(mesh.cells, static_cast<Eigen::Index>(train.size()));
    for (size_t j = 0; j < train.size(); ++j) x.col(static_cast<Eigen::Index>(j)) = transform(train[j]);
    PodOptions po;
    po.energy = 1.0;
    po.subtractMean = false;  // DEIM interpolates the field itself
    po.maxModes = o.modes;
    const auto pod = computePod(1, [&](size_t) { return x; }, mesh.V, po);
    nlohmann::json rows = nlohmann::json::array();
    for (Eigen::Index m = 1; m <= pod.modes.cols(); ++m) {
        const auto d = buildDeim(pod.modes.leftCols(m));
        const auto errors = [&](const std::vector<Eigen::VectorXd>& nus, const std::vector<double>& times) {
            double mean = 0, worst = 0, at = 0;
            for (size_t i = 0; i < nus.size(); ++i) {
                const auto& nu = nus[i];
                const Eigen::VectorXd e = back(d.reconstruct(d.sample(transform(nu)))) - nu;
                const double r = std::sqrt(e.cwiseProduct(e).dot(mesh.V) / nu.cwiseProduct(nu).dot(mesh.V));
                mean += r / double(nus.size());
                if (r > worst) worst = r, at = times[i];
            }
            return nus.empty() ? nlohmann::json() : nlohmann::json{{"mean", mean}, {"max", worst}, {"max_at_time_s", at}};
        };
        rows.push_back({{"modes", m}, {"train", errors(train, trainTimes)}, {"holdout", errors(test, testTimes)}});
        if (m == pod.modes.cols()) {
            std::vector<Eigen::Index> pts = d.points;
            rows.back()["points"] = pts;
        }
    }
    double lo = train.front().minCoeff(), hi = train.front().maxCoeff();
    for (const auto& nu : train) lo = std::min(lo, nu.minCoeff()), hi = std::max(hi, nu.maxCoeff());
    return {{"cells", mesh.cells},
            {"train_snapshots", train.size()},
            {"holdout_snapshots", test.size()},
            {"log_space", o.logSpace},
            {"nu_range", {lo, hi}},
            {"by_modes", rows}};
}

}  // namespace mixload::rom
