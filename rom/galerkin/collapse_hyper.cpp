// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/galerkin/collapse_hyper.hpp"

#include <algorithm>
#include <cmath>

#include "common/input_error.hpp"
#include "rom/galerkin/collapse_flow.hpp"
#include "rom/hyper/deim.hpp"
#include "rom/hyper/nnls.hpp"
#include "rom/operators/fv_operators.hpp"
#include "rom/pod/pod.hpp"

namespace mixload::rom {

Eigen::VectorXd ViscousHyper::strainRate(const Eigen::VectorXd& a) const {
    const Eigen::VectorXd g = gradAtPoints * a;
    Eigen::VectorXd out(size());
    for (Eigen::Index p = 0; p < out.size(); ++p) {
        out[p] = rom::strainRate(Eigen::Matrix3d(Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(g.data() + 9 * p)));
    }
    return out;
}

Eigen::VectorXd ViscousHyper::projected(const Eigen::VectorXd& muAtPoints, const Eigen::VectorXd& a) const {
    const Eigen::Index k = a.size();
    const Eigen::VectorXd v = viscous * (toCoefficients * muAtPoints);
    return Eigen::Map<const Eigen::MatrixXd>(v.data(), k, k) * a;
}

ViscousHyper buildViscousHyper(const CollapseFlow& flow, const HyperTraining& tr, HyperMethod method, int points,
                               double tolerance) {
    const CollapseGalerkin& r = flow.model();
    const FvMesh& m = r.mesh;
    const Eigen::Index K = r.flow.modes.cols(), C = m.cells, N = tr.mu.cols();
    // DEIM needs a mode per point; ECSW's count is only a cap on the cells it may keep.
    requireRange("hyper-points", points, 1, method == HyperMethod::deim ? static_cast<double>(N) : 1e9);
    if (method == HyperMethod::ecsw) requireRange("hyper-tolerance", tolerance, 0.0, 1.0, false);

    // B_c for every cell, from each mode's velocity, boundary values and gradient.
    std::vector<Vectors> U, Ub;
    std::vector<std::array<Vectors, 3>> G;
    for (Eigen::Index k = 0; k < K; ++k) {
        U.push_back(asVectors(r.cellU.col(k)));
        Ub.push_back(flow.boundaryVelocity(U.back()));
        G.push_back(gradComponents(m, U.back(), Ub.back()));
    }
    Eigen::MatrixXd B(K * K, C);
    Eigen::VectorXd unit = Eigen::VectorXd::Zero(C);
    for (Eigen::Index c = 0; c < C; ++c) {
        unit[c] = 1;
        for (Eigen::Index k = 0; k < K; ++k) {
            const auto sk = static_cast<size_t>(k);
            B.col(c).segment(k * K, K) = r.flow.modes.transpose() * flow.faceProject(flow.viscous(unit, U[sk], Ub[sk], G[sk]));
        }
        unit[c] = 0;
    }
    const auto applied = [&](Eigen::Index c, const Eigen::VectorXd& a) {
        return Eigen::Map<const Eigen::MatrixXd>(B.col(c).data(), K, K) * a;
    };
    // The exact projected term of each training snapshot; snapshots at rest carry none and are skipped.
    std::vector<Eigen::Index> used;
    std::vector<Eigen::VectorXd> exact;
    double largest = 0;
    for (Eigen::Index j = 0; j < N; ++j) {
        Eigen::VectorXd f = Eigen::VectorXd::Zero(K);
        for (Eigen::Index c = 0; c < C; ++c) f += tr.mu(c, j) * applied(c, tr.flow.col(j));
        exact.push_back(f);
        largest = std::max(largest, f.norm());
    }
    for (Eigen::Index j = 0; j < N; ++j)
        if (exact[static_cast<size_t>(j)].norm() > 1e-9 * largest) used.push_back(j);
    if (used.empty()) throw InputError("training snapshots", std::to_string(N), "snapshots with a moving flow");

    ViscousHyper h;
    h.method = method;
    if (method == HyperMethod::deim) {
        PodOptions po;
        po.energy = 1.0;
        po.maxModes = points;
        po.subtractMean = false;  // DEIM interpolates the field itself
        const PodBasis pod = computePod(1, [&](size_t) { return tr.mu; }, m.V, po);
        if (pod.modes.cols() < points)
            throw InputError("hyper-points", std::to_string(points),
                             "at most " + std::to_string(pod.modes.cols()) + " (the training viscosities' rank)");
        const Deim d = buildDeim(pod.modes);
        h.points = d.points;
        h.toCoefficients = d.pInverse;
        h.viscous = B * pod.modes;
    } else {
        // Each snapshot's block scaled by its own norm, so that every snapshot counts alike.
        Eigen::MatrixXd Gm(K * static_cast<Eigen::Index>(used.size()), C);
        Eigen::VectorXd y(Gm.rows());
        for (size_t i = 0; i < used.size(); ++i) {
            const Eigen::Index j = used[i];
            const double s = 1 / exact[static_cast<size_t>(j)].norm();
            const auto row = static_cast<Eigen::Index>(i) * K;
            for (Eigen::Index c = 0; c < C; ++c) Gm.col(c).segment(row, K) = s * tr.mu(c, j) * applied(c, tr.flow.col(j));
            y.segment(row, K) = s * exact[static_cast<size_t>(j)];
        }
        const Eigen::MatrixXd gram = Gm.transpose() * Gm;
        const SparseNnls w = sparseNnls(gram, Gm.transpose() * y, y.squaredNorm(), tolerance, std::min<Eigen::Index>(points, C));
        h.points = w.columns;
        h.toCoefficients = w.weights.asDiagonal();
        h.viscous.resize(K * K, static_cast<Eigen::Index>(w.columns.size()));
        for (size_t e = 0; e < w.columns.size(); ++e) h.viscous.col(static_cast<Eigen::Index>(e)) = B.col(w.columns[e]);
    }
    const auto P = static_cast<Eigen::Index>(h.points.size());
    h.gradAtPoints.resize(9 * P, K);
    for (Eigen::Index k = 0; k < K; ++k)
        for (Eigen::Index p = 0; p < P; ++p)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    h.gradAtPoints(9 * p + 3 * i + j, k) = G[static_cast<size_t>(k)][static_cast<size_t>(j)](h.points[static_cast<size_t>(p)], i);
    // The term's own error on the training snapshots, before any reduced model runs on it.
    double sum = 0;
    for (const Eigen::Index j : used) {
        Eigen::VectorXd muP(P);
        for (Eigen::Index p = 0; p < P; ++p) muP[p] = tr.mu(h.points[static_cast<size_t>(p)], j);
        const auto& f = exact[static_cast<size_t>(j)];
        sum += (h.projected(muP, tr.flow.col(j)) - f).squaredNorm() / f.squaredNorm();
    }
    h.trainingError = std::sqrt(sum / static_cast<double>(used.size()));
    return h;
}

}  // namespace mixload::rom
