// SPDX-License-Identifier: GPL-3.0-or-later
#include "cases/meshed_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "cases/mixer_ogrid.hpp"
#include "common/input_error.hpp"

namespace mixload::cases {

namespace {

// The thinnest paddle the scene's mesher closes to flow at cell size h.
double minThickness(scene::MixerScene s, double h) {
    s.cellSize = h;
    if (s.mesher == "ogrid") return ogridMinPaddleThickness(s);
    // snappy keeps or removes whole cells of the refined level (h / 2) around the impeller: a
    // paddle thinner than one of them is not cut as a solid.
    return 0.5 * h;
}

}  // namespace

nlohmann::json MeshedGeometry::toJson() const {
    return {{"paddle_thickness_m", paddleThickness}, {"min_paddle_thickness_m", minPaddleThickness},
            {"paddle_width_m", paddleWidth},         {"paddle_radial_m", paddleRadial},
            {"paddle_volume_m3", paddleVolume},      {"swept_volume_m3", sweptVolume}};
}

MeshedGeometry meshedGeometry(const scene::MixerScene& s) {
    const auto& g = s.geometry;
    MeshedGeometry m;
    m.minPaddleThickness = minThickness(s, s.cellSize);
    m.paddleThickness = std::max(g.paddleThickness, m.minPaddleThickness);
    m.paddleWidth = g.paddleWidth;
    m.paddleRadial = g.tipRadius() - g.shaftRadius();
    m.paddleVolume = g.paddleCount * m.paddleRadial * m.paddleWidth * m.paddleThickness;
    const double r0 = g.shaftRadius(), r1 = g.tipRadius();
    m.sweptVolume = std::numbers::pi * (r1 * r1 - r0 * r0) * (g.rotorX1() - g.rotorX0());
    return m;
}

void requireSceneGeometry(const scene::MixerScene& s) {
    const double t = s.geometry.paddleThickness, tMin = minThickness(s, s.cellSize);
    if (tMin <= t * (1 + kGeometryTolerance)) return;
    // The cell counts round up, so the thinnest paddle falls with h in steps: scan down by 0.5%.
    double h = s.cellSize;
    while (h > 1e-4 && minThickness(s, h) > t * (1 + kGeometryTolerance)) h *= 0.995;
    throw InputError("impeller.paddle_thickness_m", formatNumber(t) + " m in scene " + s.name,
                     "at least " + formatNumber(tMin / (1 + kGeometryTolerance)) + " m on the " + s.meshLabel() +
                         " mesh, whose thinnest paddle closed to flow is " + formatNumber(tMin) +
                         " m (a thinner one is thickened, so the run would simulate another impeller); " +
                         "this paddle needs cells of at most " + formatNumber(std::floor(h * 1e4) / 1e4) + " m");
}

void requireSameImpeller(const scene::MixerScene& a, const scene::MixerScene& b, const std::string& key,
                         const std::string& value) {
    const auto ga = meshedGeometry(a), gb = meshedGeometry(b);
    const auto near = [](double x, double y) { return std::abs(x - y) <= kGeometryTolerance * std::max(x, y); };
    const auto& pa = a.geometry;
    const auto& pb = b.geometry;
    if (near(ga.paddleThickness, gb.paddleThickness) && near(ga.paddleWidth, gb.paddleWidth) &&
        near(ga.paddleRadial, gb.paddleRadial) && pa.paddleCount == pb.paddleCount && pa.pitchDeg == pb.pitchDeg &&
        pa.bore == pb.bore && pa.length == pb.length)
        return;
    throw InputError(key, value,
                     "runs of the same impeller as " + a.name + " on " + a.meshLabel() + " (paddles cut " +
                         formatNumber(ga.paddleThickness * 1e3) + " x " + formatNumber(ga.paddleWidth * 1e3) +
                         " mm, " + std::to_string(pa.paddleCount) + " of them); these are " + b.name + " on " +
                         b.meshLabel() + ", paddles cut " + formatNumber(gb.paddleThickness * 1e3) + " x " +
                         formatNumber(gb.paddleWidth * 1e3) + " mm, " + std::to_string(pb.paddleCount) +
                         " of them: another impeller, not another resolution");
}

}  // namespace mixload::cases
