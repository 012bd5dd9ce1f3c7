// SPDX-License-Identifier: GPL-3.0-or-later
#include "post/bed_profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "common/input_error.hpp"

namespace mixload::post {

nlohmann::json BedProfile::toJson() const {
    nlohmann::json layersJson = nlohmann::json::array();
    for (const auto& l : layers)
        layersJson.push_back({{"x_m", l.x},
                              {"mass_kg", l.massKg},
                              {"dense_kg", l.denseKg},
                              {"dense_top_z_m", std::isfinite(l.topZ) ? nlohmann::json(l.topZ) : nlohmann::json()}});
    return {{"time_s", time}, {"loading_kg", loadingKg}, {"bulk_density_kg_m3", bulkDensity}, {"layers", layersJson}};
}

BedProfile bedProfile(const store::SnapshotFile& file, size_t timeIndex, double denseAlpha) {
    if (timeIndex >= file.times().size())
        throw InputError("time index", std::to_string(timeIndex), "below " + std::to_string(file.times().size()));
    BedProfile p;
    p.time = file.times()[timeIndex];
    const auto params = file.params();
    const auto rho = params.find("material.bulk_density_kg_m3");
    if (rho == params.end() || !rho->is_number())
        throw InputError("material.bulk_density_kg_m3", "(missing)", "a mixer snapshot's params (" + file.path().string() + ")");
    p.bulkDensity = rho->get<double>();
    const Eigen::VectorXd alpha = file.column("alpha", timeIndex);
    const Eigen::VectorXd& vol = file.cellVolumes();
    const std::vector<double> centres = file.cellCentres(timeIndex);  // moving or fixed
    const size_t n = file.cells();
    std::vector<size_t> order(n);
    std::iota(order.begin(), order.end(), size_t{0});
    std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return centres[3 * a] < centres[3 * b]; });
    for (size_t k = 0; k < n; ++k) {
        const size_t i = order[k];
        const double x = centres[3 * i], z = centres[3 * i + 2];
        if (p.layers.empty() || x - p.layers.back().x > 1e-6)
            p.layers.push_back({x, 0, 0, std::numeric_limits<double>::quiet_NaN()});
        auto& l = p.layers.back();
        const double m = alpha[static_cast<Eigen::Index>(i)] * vol[static_cast<Eigen::Index>(i)] * p.bulkDensity;
        l.massKg += m;
        if (alpha[static_cast<Eigen::Index>(i)] > denseAlpha) {
            l.denseKg += m;
            l.topZ = std::isfinite(l.topZ) ? std::max(l.topZ, z) : z;
        }
        p.loadingKg += m;
    }
    return p;
}

}  // namespace mixload::post
