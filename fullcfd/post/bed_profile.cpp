// SPDX-License-Identifier: GPL-3.0-or-later
#include "post/bed_profile.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numeric>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
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

std::optional<std::filesystem::path> plotBedProfiles(const std::vector<std::pair<std::string, BedProfile>>& profiles,
                                                     const std::filesystem::path& dir, std::string& warning) {
    std::filesystem::create_directories(dir);
    std::ostringstream dat, plotMass, plotTop;
    for (size_t k = 0; k < profiles.size(); ++k) {
        const auto& [label, p] = profiles[k];
        dat << "# " << label << " at t = " << p.time << " s, M = " << p.loadingKg << " kg\n# x_m mass_kg dense_kg dense_top_z_m\n";
        for (const auto& l : p.layers)
            dat << l.x << ' ' << l.massKg << ' ' << l.denseKg << ' ' << (std::isfinite(l.topZ) ? std::to_string(l.topZ) : "NaN") << '\n';
        dat << "\n\n";  // one gnuplot index per profile
        std::ostringstream title;
        title << label << " (M " << std::setprecision(4) << p.loadingKg << " kg)";
        plotMass << (k ? ", " : "plot ") << "'profile.dat' index " << k << " using 1:2 with linespoints lw 2 title '" << title.str() << "'";
        plotTop << (k ? ", " : "plot ") << "'profile.dat' index " << k << " using 1:4 with linespoints lw 2 title '" << title.str() << "'";
    }
    writeFileAtomic(dir / "profile.dat", dat.str());
    const std::string body = "set multiplot layout 2,1\nset key top right noenhanced\nset grid\n"
                             "set ylabel 'powder per axial layer of cells [kg]'\nset yrange [0:*]\n" + plotMass.str() + "\n"
                             "set xlabel 'x along the shaft, feed end at 0 [m]'\nset ylabel 'top of the dense powder, z [m] (axis at 0)'\n"
                             "set yrange [*:*]\n" + plotTop.str() + "\nunset multiplot\n";
    return renderPng(dir, "profile", "pngcairo size 900,800 noenhanced", body, warning);
}

}  // namespace mixload::post
