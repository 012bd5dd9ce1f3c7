// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/galerkin/collapse_hyper.hpp"

#include <algorithm>
#include <cmath>
#include <functional>

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

Eigen::MatrixXd ViscousHyper::strainRateJacobian(const Eigen::VectorXd& a, const Eigen::VectorXd& sr) const {
    // gammaDot = sqrt(2 S:S) with S = sym(G), G linear in a: d gammaDot = 2 S:dG / gammaDot.
    const Eigen::VectorXd g = gradAtPoints * a;
    Eigen::MatrixXd out = Eigen::MatrixXd::Zero(size(), a.size());
    for (Eigen::Index p = 0; p < out.rows(); ++p) {
        if (!(sr[p] > 0)) continue;
        const Eigen::Matrix3d G = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(g.data() + 9 * p);
        const Eigen::Matrix3d S = 0.5 * (G + G.transpose());
        const Eigen::Matrix<double, 9, 1> w = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(Eigen::Matrix<double, 3, 3, Eigen::RowMajor>(S).data());
        out.row(p) = (2.0 / sr[p]) * (w.transpose() * gradAtPoints.middleRows(9 * p, 9));
    }
    return out;
}

Eigen::MatrixXd ViscousHyper::jacobian(const Eigen::VectorXd& muAtPoints, const Eigen::MatrixXd& dMuDa, const Eigen::VectorXd& a) const {
    // F = sum_q c_q B_q a with c = toCoefficients mu: dF/da = sum_q c_q B_q + sum_q (B_q a) (dc_q/da)^T.
    const Eigen::Index k = a.size(), P = viscous.cols();
    const Eigen::VectorXd c = toCoefficients * muAtPoints;
    const Eigen::VectorXd sum = viscous * c;
    Eigen::MatrixXd J = Eigen::Map<const Eigen::MatrixXd>(sum.data(), k, k);
    Eigen::MatrixXd Ba(k, P);
    for (Eigen::Index q = 0; q < P; ++q) Ba.col(q) = Eigen::Map<const Eigen::MatrixXd>(viscous.col(q).data(), k, k) * a;
    J.noalias() += Ba * (toCoefficients * dMuDa);
    return J;
}

Eigen::VectorXd ViscousHyper::projected(const Eigen::VectorXd& muAtPoints, const Eigen::VectorXd& a) const {
    const Eigen::Index k = a.size();
    const Eigen::VectorXd v = viscous * (toCoefficients * muAtPoints);
    return Eigen::Map<const Eigen::MatrixXd>(v.data(), k, k) * a;
}

namespace {
// Energy-conserving sampling and weighting over training snapshots: share(j) is the K x C matrix of
// each cell's share of snapshot j's projected term. Snapshots whose term vanishes (at rest) are
// skipped; each other's block is scaled by its own norm so that every snapshot counts alike. Returns
// the kept cells with their weights and the RMS relative error over the snapshots.
std::pair<SparseNnls, double> ecsw(Eigen::Index N, const std::function<Eigen::MatrixXd(Eigen::Index)>& share, double tolerance,
                                   Eigen::Index maxCells) {
    // Two passes, so that only the scaled system is ever held (shares are cheap to recompute).
    std::vector<double> norms;
    for (Eigen::Index j = 0; j < N; ++j) norms.push_back(share(j).rowwise().sum().norm());
    const double largest = *std::max_element(norms.begin(), norms.end());
    std::vector<Eigen::Index> used;
    for (Eigen::Index j = 0; j < N; ++j)
        if (norms[static_cast<size_t>(j)] > 1e-9 * largest) used.push_back(j);
    if (used.empty()) throw InputError("training snapshots", std::to_string(N), "snapshots with a moving flow");
    Eigen::MatrixXd first = share(used.front());
    const Eigen::Index K = first.rows(), C = first.cols();
    Eigen::MatrixXd Gm(K * static_cast<Eigen::Index>(used.size()), C);
    for (size_t i = 0; i < used.size(); ++i) {
        const Eigen::Index j = used[i];
        Gm.middleRows(static_cast<Eigen::Index>(i) * K, K) = (i == 0 ? first : share(j)) / norms[static_cast<size_t>(j)];
    }
    first.resize(0, 0);
    const Eigen::VectorXd y = Gm.rowwise().sum();
    const SparseNnls w = sparseNnls(Gm.transpose() * Gm, Gm.transpose() * y, y.squaredNorm(), tolerance, std::min(maxCells, C));
    Eigen::VectorXd full = Eigen::VectorXd::Zero(C);
    for (size_t e = 0; e < w.columns.size(); ++e) full[w.columns[e]] = w.weights[static_cast<Eigen::Index>(e)];
    const Eigen::VectorXd r = Gm * full - y;
    double sum = 0;  // every block of y has norm 1
    for (size_t i = 0; i < used.size(); ++i) sum += r.segment(static_cast<Eigen::Index>(i) * K, K).squaredNorm();
    return {w, std::sqrt(sum / static_cast<double>(used.size()))};
}
}  // namespace

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
    const auto share = [&](Eigen::Index j) {
        Eigen::MatrixXd s(K, C);
        for (Eigen::Index c = 0; c < C; ++c) s.col(c) = tr.mu(c, j) * applied(c, tr.flow.col(j));
        return s;
    };
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
        // The term's own error on the training snapshots, before any reduced model runs on it.
        double sum = 0;
        Eigen::Index n = 0;
        for (Eigen::Index j = 0; j < N; ++j) {
            const Eigen::VectorXd f = share(j).rowwise().sum();
            if (!(f.norm() > 0)) continue;
            const Eigen::VectorXd muP = d.sample(tr.mu.col(j));
            sum += (h.projected(muP, tr.flow.col(j)) - f).squaredNorm() / f.squaredNorm();
            ++n;
        }
        h.trainingError = std::sqrt(sum / static_cast<double>(std::max<Eigen::Index>(n, 1)));
    } else {
        const auto [w, error] = ecsw(N, share, tolerance, points);
        h.points = w.columns;
        h.toCoefficients = w.weights.asDiagonal();
        h.viscous.resize(K * K, static_cast<Eigen::Index>(w.columns.size()));
        for (size_t e = 0; e < w.columns.size(); ++e) h.viscous.col(static_cast<Eigen::Index>(e)) = B.col(w.columns[e]);
        h.trainingError = error;
    }
    const auto P = static_cast<Eigen::Index>(h.points.size());
    h.gradAtPoints.resize(9 * P, K);
    for (Eigen::Index k = 0; k < K; ++k)
        for (Eigen::Index p = 0; p < P; ++p)
            for (int i = 0; i < 3; ++i)
                for (int j = 0; j < 3; ++j)
                    h.gradAtPoints(9 * p + 3 * i + j, k) = G[static_cast<size_t>(k)][static_cast<size_t>(j)](h.points[static_cast<size_t>(p)], i);
    return h;
}

Eigen::VectorXd ConvectionHyper::projected(const Eigen::VectorXd& rho, const Eigen::VectorXd& a) const {
    const Eigen::VectorXd q = faceFlux * a, u = faceVelocity * a;
    Eigen::VectorXd conv(3 * size());
    for (Eigen::Index e = 0; e < size(); ++e) {
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        for (Eigen::Index f = faceStart[static_cast<size_t>(e)]; f < faceStart[static_cast<size_t>(e) + 1]; ++f) c += q[f] * u.segment<3>(3 * f);
        conv.segment<3>(3 * e) = -rho[cells[static_cast<size_t>(e)]] * c;
    }
    return project * conv;
}

Eigen::MatrixXd ConvectionHyper::jacobian(const Eigen::VectorXd& rho, const Eigen::VectorXd& a) const {
    // conv_e = -rho_e sum_f q_f u_f with q and u linear in a: d conv_e = -rho_e sum_f (u_f dq_f + q_f du_f).
    const Eigen::VectorXd q = faceFlux * a, u = faceVelocity * a;
    Eigen::MatrixXd dconv(3 * size(), a.size());
    for (Eigen::Index e = 0; e < size(); ++e) {
        Eigen::MatrixXd d = Eigen::MatrixXd::Zero(3, a.size());
        for (Eigen::Index f = faceStart[static_cast<size_t>(e)]; f < faceStart[static_cast<size_t>(e) + 1]; ++f)
            d += u.segment<3>(3 * f) * faceFlux.row(f) + q[f] * faceVelocity.middleRows(3 * f, 3);
        dconv.middleRows(3 * e, 3) = -rho[cells[static_cast<size_t>(e)]] * d;
    }
    return project * dconv;
}

ConvectionHyper buildConvectionHyper(const CollapseFlow& flow, const HyperTraining& tr, int points, double tolerance) {
    const CollapseGalerkin& r = flow.model();
    const FvMesh& m = r.mesh;
    const Eigen::MatrixXd& Psi = r.flow.modes;
    const Eigen::Index K = Psi.cols(), C = m.cells, N = tr.flow.cols();
    requireRange("hyper-points", points, 1, 1e9);
    requireRange("hyper-tolerance", tolerance, 0.0, 1.0, false);
    // Each cell's faces with the cell's side (+1 owner, -1 neighbour) and share of the face's
    // interpolation (the owner's weight, 1 - it for the neighbour, 1 on a boundary face).
    struct Side { Eigen::Index face; double sign, share; };
    std::vector<std::vector<Side>> sides(static_cast<size_t>(C));
    for (Eigen::Index f = 0; f < m.faces(); ++f) {
        const bool internal = f < m.internalFaces;
        sides[static_cast<size_t>(m.owner[f])].push_back({f, 1.0, internal ? m.weights[f] : 1.0});
        if (internal) sides[static_cast<size_t>(m.neighbour[f])].push_back({f, -1.0, 1 - m.weights[f]});
    }
    // Each mode's face velocity (linear interpolation, the walls' boundary values).
    Eigen::MatrixXd faceU(3 * m.faces(), K);
    for (Eigen::Index k = 0; k < K; ++k) {
        const Vectors U = asVectors(r.cellU.col(k)), Ub = flow.boundaryVelocity(U);
        for (int j = 0; j < 3; ++j) {
            const Eigen::VectorXd uf = interpolate(m, U.col(j), Ub.col(j));
            for (Eigen::Index f = 0; f < m.faces(); ++f) faceU(3 * f + j, k) = uf[f];
        }
    }
    // P_c / V_c: cell c's acceleration onto the modes through the face projection.
    const Eigen::VectorXd Vf = m.magSf.cwiseQuotient(m.deltaCoeffs);
    std::vector<Eigen::MatrixXd> P(static_cast<size_t>(C));
    for (Eigen::Index c = 0; c < C; ++c) {
        auto& pc = P[static_cast<size_t>(c)];
        pc = Eigen::MatrixXd::Zero(K, 3);
        for (const auto& s : sides[static_cast<size_t>(c)])
            pc += Psi.row(s.face).transpose() * (Vf[s.face] / m.magSf[s.face] * s.share / m.V[c]) * m.Sf.row(s.face);
    }
    // Cell c's share of snapshot j's projected convection: -rho_c P_c / V_c sum_f +-phi_f U_f.
    const auto cellShare = [&](Eigen::Index c, const Eigen::VectorXd& q, const Eigen::VectorXd& u, double rhoC) {
        Eigen::Vector3d acc = Eigen::Vector3d::Zero();
        for (const auto& s : sides[static_cast<size_t>(c)]) acc += s.sign * q[s.face] * u.segment<3>(3 * s.face);
        return Eigen::VectorXd(-rhoC * (P[static_cast<size_t>(c)] * acc));
    };
    const auto share = [&](Eigen::Index j) {
        const Eigen::VectorXd a = tr.flow.col(j);
        const Eigen::VectorXd q = m.magSf.cwiseProduct(Psi * a), u = faceU * a;
        Eigen::MatrixXd s(K, C);
        for (Eigen::Index c = 0; c < C; ++c) s.col(c) = cellShare(c, q, u, tr.rho(c, j));
        return s;
    };
    const auto [w, error] = ecsw(N, share, tolerance, points);
    ConvectionHyper h;
    h.cells = w.columns;
    h.trainingError = error;
    const auto E = static_cast<Eigen::Index>(w.columns.size());
    h.project.resize(K, 3 * E);
    h.faceStart.push_back(0);
    std::vector<Eigen::Index> faces;
    std::vector<double> signs;
    for (Eigen::Index e = 0; e < E; ++e) {
        const Eigen::Index c = w.columns[static_cast<size_t>(e)];
        h.project.middleCols(3 * e, 3) = w.weights[e] * P[static_cast<size_t>(c)];
        for (const auto& s : sides[static_cast<size_t>(c)]) faces.push_back(s.face), signs.push_back(s.sign);
        h.faceStart.push_back(static_cast<Eigen::Index>(faces.size()));
    }
    const auto F = static_cast<Eigen::Index>(faces.size());
    h.faceFlux.resize(F, K);
    h.faceVelocity.resize(3 * F, K);
    for (Eigen::Index i = 0; i < F; ++i) {
        const Eigen::Index f = faces[static_cast<size_t>(i)];
        h.faceFlux.row(i) = signs[static_cast<size_t>(i)] * m.magSf[f] * Psi.row(f);
        h.faceVelocity.middleRows(3 * i, 3) = faceU.middleRows(3 * f, 3);
    }
    return h;
}

}  // namespace mixload::rom
