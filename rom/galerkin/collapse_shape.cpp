// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/galerkin/collapse_shape.hpp"

#include <algorithm>
#include <cmath>
#include <map>

#include "common/input_error.hpp"

namespace mixload::rom {

CollapseShape CollapseShape::fromCase(const store::CaseFile& f) {
    const auto p = f.params();
    if (p.value("scene", std::string()) != "collapse2d")
        throw InputError("snapshot file", f.path().string(), "a collapse2d run's snapshots");
    CollapseShape s;
    s.length = p.at("length_m").get<double>();
    s.height = p.at("aspect").get<double>() * s.length;
    s.binWidth = s.length / p.at("cells_per_length").get<double>();
    const auto pts = f.meshDoubles("points");
    double x1 = 0, z0 = 1e300, z1 = -1e300;
    for (size_t i = 0; i + 2 < pts.size(); i += 3) {
        x1 = std::max(x1, pts[i]);
        z0 = std::min(z0, pts[i + 2]);
        z1 = std::max(z1, pts[i + 2]);
    }
    s.depth = z1 - z0;
    s.bins = static_cast<int>(std::lround(x1 / s.binWidth));
    return s;
}

Eigen::VectorXd CollapseShape::profile(const FvMesh& m, const Eigen::VectorXd& alpha) const {
    Eigen::VectorXd h = Eigen::VectorXd::Zero(bins);
    for (Eigen::Index c = 0; c < m.cells; ++c) {
        const auto b = static_cast<long>(std::floor(m.C(c, 0) / binWidth));
        if (b >= 0 && b < bins) h[b] += alpha[c] * m.V[c];
    }
    return h / (binWidth * depth);
}

double CollapseShape::front(const Eigen::VectorXd& h) const {
    const double hMin = 0.5 * binWidth;
    long last = -1;
    for (long i = 0; i < h.size(); ++i)
        if (h[i] >= hMin) last = i;
    if (last < 0) return 0;
    const double edge = (last + 1) * binWidth;
    if (last + 1 >= h.size()) return edge;
    return edge + std::min(h[last + 1] / hMin, 1.0) * binWidth;
}

double CollapseShape::runoutStar(const FvMesh& m, const Eigen::VectorXd& alpha) const {
    return (front(profile(m, alpha)) - length) / length;
}

double CollapseShape::heightStar(const FvMesh& m, const Eigen::VectorXd& alpha) const {
    return profile(m, alpha).maxCoeff() / height;
}

Eigen::VectorXd CollapseShape::initialAlpha(const FvMesh& m) const {
    // The grid's cells are squares of side binWidth (fullcfd/cases/collapse2d: columnOverlap).
    const auto overlap = [&](double c, double end) {
        const double lo = c - 0.5 * binWidth, hi = c + 0.5 * binWidth;
        return std::max(0.0, std::min(hi, end) - std::max(lo, 0.0)) / binWidth;
    };
    Eigen::VectorXd a(m.cells);
    for (Eigen::Index c = 0; c < m.cells; ++c) a[c] = overlap(m.C(c, 0), length) * overlap(m.C(c, 1), height);
    return a;
}

ColumnPressure::ColumnPressure(const FvMesh& m, double gravity) : g_(gravity) {
    // Columns: cells whose centres share x (to a thousandth of the smallest cell) and z.
    double minSize = 1e300;
    for (Eigen::Index c = 0; c < m.cells; ++c) minSize = std::min(minSize, std::cbrt(m.V[c]));
    const double tol = 1e-3 * minSize;
    std::map<std::pair<long long, long long>, std::vector<Eigen::Index>> byColumn;
    for (Eigen::Index c = 0; c < m.cells; ++c)
        byColumn[{std::llround(m.C(c, 0) / tol), std::llround(m.C(c, 2) / tol)}].push_back(c);
    halfHeight_.resize(m.cells);
    for (auto& [key, cells] : byColumn) {
        std::sort(cells.begin(), cells.end(), [&](auto a, auto b) { return m.C(a, 1) > m.C(b, 1); });
        // Half heights from the spacing of consecutive centres (a uniform column: half a cell).
        for (size_t i = 0; i < cells.size(); ++i) {
            const double gap = cells.size() == 1 ? std::cbrt(m.V[cells[i]])
                               : i + 1 < cells.size() ? m.C(cells[i], 1) - m.C(cells[i + 1], 1)
                                                      : m.C(cells[i - 1], 1) - m.C(cells[i], 1);
            halfHeight_[cells[i]] = 0.5 * gap;
        }
        columns_.push_back(std::move(cells));
    }
    // A columnar grid: every column as tall as the others (the same number of cells).
    for (const auto& col : columns_)
        if (col.size() != columns_.front().size())
            throw InputError("mesh", std::to_string(columns_.size()) + " columns of unequal cell counts",
                             "cells standing in vertical columns (a structured 2D grid)");
}

Eigen::VectorXd ColumnPressure::operator()(const Eigen::VectorXd& rho) const {
    Eigen::VectorXd p(rho.size());
    for (const auto& col : columns_) {
        double above = 0;
        for (const auto c : col) {
            p[c] = above + rho[c] * g_ * halfHeight_[c];
            above = p[c] + rho[c] * g_ * halfHeight_[c];
        }
    }
    return p;
}

}  // namespace mixload::rom
