// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/collapse_galerkin.hpp"
#include "common/clock.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "common/input_error.hpp"
#include "rom/alpha_transport.hpp"
#include "rom/cvode_integrator.hpp"
#include "rom/fv_operators.hpp"

#include <Eigen/Sparse>

namespace mixload::rom {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;


// Owner values on the boundary faces (zero gradient).
Eigen::VectorXd ownerValues(const FvMesh& m, const Eigen::VectorXd& cells) {
    Eigen::VectorXd b(m.boundaryFaces);
    for (Eigen::Index i = 0; i < m.boundaryFaces; ++i) b[i] = cells[m.owner[m.internalFaces + i]];
    return b;
}

// The collapse2d scene's velocity conditions, by patch (fullcfd/cases/collapse2d.cpp).
std::vector<CollapseGalerkin::Wall> collapseWalls(const FvMesh& m) {
    std::vector<CollapseGalerkin::Wall> w(static_cast<size_t>(m.boundaryFaces));
    for (const auto& p : m.patches) {
        CollapseGalerkin::Wall kind;
        if (p.name == "bottom") kind = CollapseGalerkin::Wall::noSlip;
        else if (p.name == "leftWall") kind = CollapseGalerkin::Wall::slip;
        else if (p.name == "atmosphere") kind = CollapseGalerkin::Wall::open;
        else throw InputError("patch", p.name, "the collapse2d patches bottom, leftWall and atmosphere");
        for (Eigen::Index i = 0; i < p.size; ++i) w[static_cast<size_t>(p.start - m.internalFaces + i)] = kind;
    }
    return w;
}

// What the flow equations hold fixed over one step: the densities, viscosity mixture inputs, the
// lithostatic pressure, the reduced mass matrix and gravity term, all from alpha.
struct Frozen {
    Eigen::VectorXd alpha, rhoC, rhoF, p, gravityFaces, gravityTerm;
    Eigen::MatrixXd mass;
    Eigen::LLT<Eigen::MatrixXd> massLlt;
};

class Model {
  public:
    explicit Model(const CollapseGalerkin& r)
        : r_(r), m_(r.mesh), pressure_(r.mesh, r.gravity), Vf_(m_.magSf.cwiseQuotient(m_.deltaCoeffs)),
          ghf_(-r.gravity * m_.Cf.col(1)) {
        // The pressure recovery's normal equations: the face-difference operator weighted by
        // |Sf| deltaCoeff (the FV Laplacian), p_rgh = 0 on the open faces; constant, factored once.
        std::vector<Eigen::Triplet<double>> t;
        for (Eigen::Index f = 0; f < m_.faces(); ++f) {
            const double w = m_.magSf[f] * m_.deltaCoeffs[f];
            const auto o = m_.owner[f];
            if (f < m_.internalFaces) {
                const auto n = m_.neighbour[f];
                t.emplace_back(o, o, w);
                t.emplace_back(n, n, w);
                t.emplace_back(o, n, -w);
                t.emplace_back(n, o, -w);
            } else if (r_.walls[static_cast<size_t>(f - m_.internalFaces)] == CollapseGalerkin::Wall::open) {
                t.emplace_back(o, o, w);
            }
        }
        Eigen::SparseMatrix<double> L(m_.cells, m_.cells);
        L.setFromTriplets(t.begin(), t.end());
        poisson_.compute(L);
        if (poisson_.info() != Eigen::Success) throw std::runtime_error("pressure recovery: the Laplacian is singular");
    }

    Frozen freeze(const Eigen::VectorXd& alphaIn) const {
        Frozen z;
        z.alpha = clampFraction(alphaIn);
        const double rho1 = r_.law.rho, rho2 = r_.airRho;
        z.rhoC = (rho2 + (rho1 - rho2) * z.alpha.array()).matrix();
        z.rhoF = interpolate(m_, z.rhoC, ownerValues(m_, z.rhoC));
        z.p = pressure_(z.rhoC);
        const Eigen::MatrixXd& Psi = r_.flow.modes;
        z.mass = Psi.transpose() * (Vf_.cwiseProduct(z.rhoF).asDiagonal() * Psi);
        z.massLlt.compute(z.mass);
        z.gravityFaces = Eigen::VectorXd::Zero(m_.faces());
        for (Eigen::Index i = 0; i < m_.internalFaces; ++i)
            z.gravityFaces[i] = -m_.magSf[i] * ghf_[i] * (z.rhoC[m_.neighbour[i]] - z.rhoC[m_.owner[i]]);
        z.gravityTerm = Psi.transpose() * z.gravityFaces;
        return z;
    }

    // The total pressure the reduced flow implies: per face, the momentum the projection left
    // unbalanced, rho_f V_f dv_f/dt - V_f F_f - gravity_f, is the pressure's -|Sf| (p_N - p_O);
    // its gradient part, found by least squares (a Poisson equation), is p_rgh, and p = p_rgh + rho gh.
    Eigen::VectorXd recoverPressure(const Frozen& z, const Eigen::VectorXd& a) const {
        const Eigen::VectorXd force = faceForce(z, a);
        const Eigen::VectorXd dadt = z.massLlt.solve(r_.flow.modes.transpose() * force + z.gravityTerm);
        const Eigen::VectorXd residual =
            Vf_.cwiseProduct(z.rhoF).cwiseProduct(r_.flow.modes * dadt) - force - z.gravityFaces;
        Eigen::VectorXd b = Eigen::VectorXd::Zero(m_.cells);
        for (Eigen::Index f = 0; f < m_.faces(); ++f) {
            const bool internal = f < m_.internalFaces;
            if (!internal && r_.walls[static_cast<size_t>(f - m_.internalFaces)] != CollapseGalerkin::Wall::open) continue;
            const double jump = -residual[f] / m_.magSf[f];  // p_N - p_O (p_b - p_O on an open face, p_b = 0)
            const double w = m_.magSf[f] * m_.deltaCoeffs[f];
            b[m_.owner[f]] -= w * jump;
            if (internal) b[m_.neighbour[f]] += w * jump;
        }
        const Eigen::VectorXd prgh = poisson_.solve(b);
        return prgh + z.rhoC.cwiseProduct(-r_.gravity * m_.C.col(1));
    }

    Vectors cellVelocity(const Eigen::VectorXd& a) const { return asVectors(r_.cellU * a); }

    Vectors boundaryVelocity(const Vectors& U) const {
        Vectors b(m_.boundaryFaces, 3);
        for (Eigen::Index i = 0; i < m_.boundaryFaces; ++i) {
            const Eigen::Index f = m_.internalFaces + i;
            const Eigen::RowVector3d up = U.row(m_.owner[f]);
            switch (r_.walls[static_cast<size_t>(i)]) {
                case CollapseGalerkin::Wall::noSlip: b.row(i).setZero(); break;
                case CollapseGalerkin::Wall::slip: {
                    const Eigen::RowVector3d n = m_.Sf.row(f) / m_.magSf[f];
                    b.row(i) = up - up.dot(n) * n;
                    break;
                }
                case CollapseGalerkin::Wall::open: b.row(i) = up; break;
            }
        }
        return b;
    }

    // M da/dt = the projected convection, viscous and gravity terms.
    Eigen::VectorXd rate(const Frozen& z, const Eigen::VectorXd& a) const {
        return z.massLlt.solve(r_.flow.modes.transpose() * faceForce(z, a) + z.gravityTerm);
    }

    // Per face: V_f n_f . interp(-rho (U.grad)U + div(mu (grad U + dev2 grad U^T))).
    Eigen::VectorXd faceForce(const Frozen& z, const Eigen::VectorXd& a) const {
        const Eigen::VectorXd flux = m_.magSf.cwiseProduct(r_.flow.modes * a);
        const Vectors U = cellVelocity(a);
        const Vectors Ub = boundaryVelocity(U);
        const auto G = gradComponents(m_, U, Ub);
        const Eigen::VectorXd nu1 = r_.law.nu(strainRate(G), z.p);
        const Eigen::VectorXd mu =
            (z.alpha.array() * r_.law.rho * nu1.array() + (1 - z.alpha.array()) * r_.airRho * r_.airNu).matrix();
        const Eigen::VectorXd muF = interpolate(m_, mu, ownerValues(m_, mu));
        // The explicit part of interFoam's divDevRhoReff: div(mu dev2(grad(U)^T)), the face vector
        // Sf . T_f with T linearly interpolated (owner value on boundary faces), in one pass.
        std::vector<Eigen::Matrix3d> T(static_cast<size_t>(m_.cells));
        for (Eigen::Index c = 0; c < m_.cells; ++c) {
            Eigen::Matrix3d g;  // g(i, j) = dU_j/dx_i, OpenFOAM's grad(U)
            for (int j = 0; j < 3; ++j) g.col(j) = G[static_cast<size_t>(j)].row(c).transpose();
            T[static_cast<size_t>(c)] = mu[c] * (g.transpose() - 2.0 / 3.0 * g.trace() * Eigen::Matrix3d::Identity());
        }
        std::array<Eigen::VectorXd, 3> tf;
        for (auto& v : tf) v.resize(m_.faces());
        for (Eigen::Index f = 0; f < m_.faces(); ++f) {
            const auto& To = T[static_cast<size_t>(m_.owner[f])];
            const Eigen::Matrix3d Tf = f < m_.internalFaces
                                           ? Eigen::Matrix3d(m_.weights[f] * To + (1 - m_.weights[f]) * T[static_cast<size_t>(m_.neighbour[f])])
                                           : To;
            const Eigen::RowVector3d st = m_.Sf.row(f) * Tf;
            for (int j = 0; j < 3; ++j) tf[static_cast<size_t>(j)][f] = st[j];
        }
        Vectors A(m_.cells, 3);
        for (int j = 0; j < 3; ++j) {
            const Eigen::VectorXd uj = U.col(j), ubj = Ub.col(j);
            const Eigen::VectorXd conv = div(m_, flux.cwiseProduct(interpolate(m_, uj, ubj)));
            A.col(j) = -z.rhoC.cwiseProduct(conv) + laplacian(m_, muF, uj, ubj) + div(m_, tf[j]);
        }
        // n_f . interp(A)_f, weighted by the face volume.
        Eigen::VectorXd faceForce(m_.faces());
        for (Eigen::Index f = 0; f < m_.faces(); ++f) {
            Eigen::RowVector3d af = A.row(m_.owner[f]);
            if (f < m_.internalFaces) af = m_.weights[f] * af + (1 - m_.weights[f]) * A.row(m_.neighbour[f]);
            faceForce[f] = Vf_[f] * af.dot(m_.Sf.row(f)) / m_.magSf[f];
        }
        return faceForce;
    }

    Eigen::VectorXd flux(const Eigen::VectorXd& a) const { return m_.magSf.cwiseProduct(r_.flow.modes * a); }

    // Coefficients of a flux in the density-weighted product at alpha.
    Eigen::VectorXd project(const Frozen& z, const Eigen::VectorXd& phi) const {
        const Eigen::VectorXd v = phi.cwiseQuotient(m_.magSf);
        return z.massLlt.solve(r_.flow.modes.transpose() * Vf_.cwiseProduct(z.rhoF).cwiseProduct(v));
    }

    double potentialEnergy(const Eigen::VectorXd& alpha) const {
        const double y0 = m_.C.col(1).minCoeff();
        return r_.law.rho * r_.gravity * (alpha.cwiseProduct(m_.V).array() * (m_.C.col(1).array() - y0)).sum();
    }

    const ColumnPressure& pressure() const { return pressure_; }

  private:
    const CollapseGalerkin& r_;
    const FvMesh& m_;
    ColumnPressure pressure_;
    Eigen::VectorXd Vf_, ghf_;
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> poisson_;
};

}  // namespace

CollapseGalerkin CollapseGalerkin::fromCase(const store::CaseFile& f) {
    CollapseGalerkin r;
    r.shape = CollapseShape::fromCase(f);
    r.mesh = FvMesh::fromCase(f);
    r.law = GranularLaw::fromCase(f);
    const auto t = f.powderTransport();
    if (!t.contains("airRho") || !t.contains("airNu"))
        throw InputError("snapshot file", f.path().string(),
                         "snapshots exported with the air's density and viscosity (export them again)");
    r.airRho = t["airRho"].get<double>();
    r.airNu = t["airNu"].get<double>();
    r.gravity = f.params().at("gravity_m_s2").get<double>();
    r.tStar = std::sqrt(r.shape.height / r.gravity);
    r.walls = collapseWalls(r.mesh);
    return r;
}

CollapseGalerkin CollapseGalerkin::build(const std::vector<const store::SnapshotFile*>& files,
                                         const CollapseGalerkinOptions& o) {
    const auto t0 = Clock::now();
    if (files.empty()) throw InputError("FILES", "(none)", "one or more collapse snapshot files");
    if (o.trainEvery < 1) throw InputError("train-every", std::to_string(o.trainEvery), "1 or more");
    if (o.modes < 0) throw InputError("modes", std::to_string(o.modes), "0 (by energy) or more");
    const store::SnapshotFile& first = *files.front();
    for (const auto* f : files)
        if (f->meshFingerprint() != first.meshFingerprint())
            throw InputError("snapshot file", f->path().string(), "runs on one mesh (the same aspect ratio and cells as " +
                                                                       first.path().string() + ")");
    CollapseGalerkin r = fromCase(first);
    r.options = o;
    r.meshFingerprint = first.meshFingerprint();
    const auto& m = r.mesh;

    // Training columns: every k-th stored time of every file.
    std::vector<std::pair<const store::SnapshotFile*, size_t>> cols;
    for (const auto* f : files) {
        r.trainFiles.push_back(f->path().string());
        const auto t = f->powderTransport();
        r.sources.push_back({{"file", fs::absolute(f->path()).string()},
                             {"scene_hash", f->provenance().value("scene_hash", std::string())},
                             {"times", f->times().size()},
                             {"mu_s", t.value("muS", 0.0)},
                             {"mu_d", t.value("muD", 0.0)},
                             {"i0", t.value("I0", 0.0)}});
        for (size_t i = 0; i < f->times().size(); i += static_cast<size_t>(o.trainEvery)) cols.emplace_back(f, i);
    }
    r.trainTimes = cols.size();
    if (cols.size() < 2) throw InputError("snapshot file", first.path().string(), "at least two training times");
    const auto nCols = static_cast<Eigen::Index>(cols.size());

    // The flow's POD in the face product weighted by the mean density of the training times, the
    // product the projection uses (so that the modes rank the powder's motion, not the air's).
    Eigen::VectorXd rhoMean = Eigen::VectorXd::Zero(m.faces());
    for (const auto& [f, i] : cols) {
        const Eigen::VectorXd a = clampFraction(f->column("alpha", i));
        const Eigen::VectorXd rho = (r.airRho + (r.law.rho - r.airRho) * a.array()).matrix();
        rhoMean += interpolate(m, rho, ownerValues(m, rho));
    }
    rhoMean /= static_cast<double>(cols.size());
    const Eigen::VectorXd weights = m.magSf.cwiseQuotient(m.deltaCoeffs).cwiseProduct(rhoMean);
    PodOptions po;
    po.maxModes = o.modes;
    po.energy = o.modes > 0 ? 1.0 : o.energy;
    po.subtractMean = false;  // the collapse starts and ends at rest
    r.flow = computePod(
        1,
        [&](size_t) {
            Eigen::MatrixXd v(m.faces(), nCols);
            for (Eigen::Index k = 0; k < nCols; ++k)
                v.col(k) = cols[static_cast<size_t>(k)].first->faceColumn("phi", cols[static_cast<size_t>(k)].second)
                               .cwiseQuotient(m.magSf);
            return v;
        },
        weights, po);
    r.cellU.resize(3 * m.cells, r.flow.modes.cols());
    for (Eigen::Index k = 0; k < r.flow.modes.cols(); ++k) {
        const Vectors u = reconstruct(m, m.magSf.cwiseProduct(r.flow.modes.col(k)));
        r.cellU.col(k) = Eigen::Map<const Eigen::VectorXd>(u.data(), 3 * m.cells);
    }

    if (o.reducedAlpha) {
        // alpha = the initial column + modes of what the runs made of it.
        r.alphaLift = r.shape.initialAlpha(m);
        PodOptions pa;
        pa.maxModes = o.alphaModes;
        pa.energy = o.alphaModes > 0 ? 1.0 : o.alphaEnergy;
        pa.subtractMean = false;
        r.alpha = computePod(
            1,
            [&](size_t) {
                Eigen::MatrixXd x(m.cells, nCols);
                for (Eigen::Index k = 0; k < nCols; ++k)
                    x.col(k) = cols[static_cast<size_t>(k)].first->column("alpha", cols[static_cast<size_t>(k)].second) -
                               r.alphaLift;
                return x;
            },
            m.V, pa);
    }
    r.buildSeconds = secondsSince(t0);
    return r;
}

CollapseTrajectory runCollapseGalerkin(const CollapseGalerkin& rom, const Eigen::VectorXd& alpha0,
                                       const Eigen::VectorXd& phi0, double t0, const std::vector<double>& outputs,
                                       const StoredFields& stored) {
    const auto wall0 = Clock::now();
    const auto& m = rom.mesh;
    const auto& o = rom.options;
    Model model(rom);
    CollapseTrajectory out;

    Eigen::VectorXd alpha = alpha0, b;
    if (rom.alpha) {
        b = rom.alpha->project(alpha0 - rom.alphaLift);
        alpha = rom.alphaLift + rom.alpha->modes * b;
    }
    Frozen z = model.freeze(alpha);
    Eigen::VectorXd a = model.project(z, phi0);
    const double volume0 = alpha.dot(m.V);
    const double energyBound = model.potentialEnergy(clampFraction(alpha));

    const Frozen* current = &z;
    CvodeIntegrator ode(
        a.size(), [&](double, const Eigen::VectorXd& y, Eigen::VectorXd& dy) { dy = model.rate(*current, y); }, o.rtol,
        Eigen::VectorXd::Constant(a.size(), 1e-10));

    double t = t0;
    const double maxStep = o.maxStepTstar * rom.tStar;
    for (const double tOut : outputs) {
        if (!(tOut > t)) throw InputError("output time", std::to_string(tOut), "times after the start, increasing");
        while (t < tOut * (1 - 1e-12)) {
            const Eigen::VectorXd flux = stored.flux ? stored.flux(t) : model.flux(a);
            const double dt = std::min({transportStep(m, flux, o.courant), maxStep, tOut - t});
            const Eigen::VectorXd next = advanceAlpha(m, alpha, flux, dt, 0.0, o.cAlpha);
            if (rom.alpha) {
                b += rom.alpha->modes.transpose() * m.V.cwiseProduct(next - alpha);
                alpha = rom.alphaLift + rom.alpha->modes * b;
            } else {
                alpha = next;
                const Eigen::VectorXd clipped = clampFraction(alpha);
                out.clippedVolume += (alpha - clipped).cwiseAbs().dot(m.V);
                alpha = clipped;
            }
            z = model.freeze(alpha);
            if (stored.pressure) z.p = stored.pressure(t + dt);
            else if (o.pressure == PressureClosure::recovered) z.p = model.recoverPressure(z, a);
            try {
                if (stored.flux) a = model.project(z, stored.flux(t + dt));
                else ode.advance(t, t + dt, a, o.restartEachStep);
            } catch (const std::runtime_error& e) {
                throw RomFailure(std::string("reduced collapse model: the flow integration failed at t = ") +
                                 std::to_string(t) + " s (" + e.what() + ")");
            }
            t += dt;
            ++out.steps;
            const double ke = 0.5 * a.dot(z.mass * a);
            const double vol = alpha.dot(m.V);
            std::ostringstream why;
            if (!a.allFinite() || !alpha.allFinite())
                why << "its state is no longer finite";
            else if (ke > energyBound)
                why << "its kinetic energy " << ke << " J exceeds the potential energy the column can release ("
                    << energyBound << " J)";
            else if (std::abs(vol - volume0) > o.massTolerance * volume0)
                why << "its powder volume drifted by " << 100 * (vol - volume0) / volume0 << "% (tolerance "
                    << 100 * o.massTolerance << "%)";
            if (!why.str().empty()) {
                std::ostringstream msg;
                msg << "reduced collapse model unstable at t = " << t << " s (" << t / rom.tStar << " t*, step "
                    << out.steps << "): " << why.str() << "; try fewer modes, a smaller --courant or more snapshots";
                throw RomFailure(msg.str());
            }
        }
        out.times.push_back(tOut);
        out.alpha.push_back(alpha);
        out.flow.push_back(a);
        out.pressure.push_back(z.p);
        out.kineticEnergy.push_back(0.5 * a.dot(z.mass * a));
        out.powderVolume.push_back(alpha.dot(m.V));
    }
    out.odeSteps = ode.steps();
    out.rhsEvaluations = ode.rhsEvaluations();
    out.jacobianEvaluations = ode.jacobianEvaluations();
    out.wallSeconds = secondsSince(wall0);
    return out;
}

namespace {
double weightedNorm(const Eigen::VectorXd& x, const Eigen::VectorXd& w) { return std::sqrt(x.cwiseAbs2().dot(w)); }
Eigen::VectorXd perComponent(const Eigen::VectorXd& V) {  // cell volumes repeated for 3 components
    Eigen::VectorXd w(3 * V.size());
    for (Eigen::Index c = 0; c < V.size(); ++c) w.segment<3>(3 * c).setConstant(V[c]);
    return w;
}
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
    const Eigen::VectorXd wU = perComponent(m.V);
    bool trainedOn = false;
    for (const auto& t : rom.trainFiles) trainedOn = trainedOn || fs::absolute(t) == fs::absolute(f.path());

    // The pressure closure on the stored fields: lithostatic against the solver's p, in the powder,
    // and what it does to the mu(I) viscosity there.
    const ColumnPressure lith(m, rom.gravity);
    double pErr = 0, nuErr = 0, pModel = 0;
    std::vector<double> pErrAt(times.size()), pModelAt(times.size());
    for (size_t i = 0; i < times.size(); ++i) {
        const Eigen::VectorXd al = clampFraction(f.column("alpha", i));
        const Eigen::VectorXd rho = (rom.airRho + (rom.law.rho - rom.airRho) * al.array()).matrix();
        const Eigen::VectorXd p = f.column("p", i), pl = lith(rho);
        const Eigen::VectorXd w = al.cwiseProduct(m.V);
        pErrAt[i] = weightedNorm(pl - p, w) / weightedNorm(p, w);
        pErr += pErrAt[i];
        const Eigen::VectorXd sr = strainRate(m, asVectors(f.column("U", i)), asVectors(f.boundaryColumn("U", i)));
        const Eigen::VectorXd nu = rom.law.nu(sr, p), nul = rom.law.nu(sr, pl);
        nuErr += weightedNorm(nul - nu, w) / weightedNorm(nu, w);
    }

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

    double peakU = 0;
    std::vector<Eigen::VectorXd> Us;
    for (size_t i = 0; i < times.size(); ++i) {
        Us.push_back(f.column("U", i));
        peakU = std::max(peakU, weightedNorm(Us.back(), wU));
    }

    nlohmann::json rows = nlohmann::json::array();
    double aSum = 0, aMax = 0, uSum = 0, uMax = 0, aHold = 0, uHold = 0, aProjSum = 0, uProjSum = 0;
    int held = 0;
    for (size_t i = 0; i < times.size(); ++i) {
        const bool trained = trainedOn && i % static_cast<size_t>(options.trainEvery) == 0;
        const Eigen::VectorXd as = f.column("alpha", i);
        const Eigen::VectorXd& ar = tr.alpha[i];
        const double aErr = weightedNorm(ar - as, m.V) / weightedNorm(as, m.V);
        const Eigen::VectorXd Ur = rom.cellU * tr.flow[i];
        const double uErr = weightedNorm(Ur - Us[i], wU) / peakU;
        {
            const Eigen::VectorXd w = clampFraction(as).cwiseProduct(m.V), ps = f.column("p", i);
            pModelAt[i] = weightedNorm(tr.pressure[i] - ps, w) / weightedNorm(ps, w);
            pModel += pModelAt[i];
        }
        // Lower bounds: the stored fields' own projections on the bases.
        const Eigen::VectorXd phi = f.faceColumn("phi", i);
        const Eigen::VectorXd aProj = rom.flow.project(phi.cwiseQuotient(m.magSf));
        const double uProj = weightedNorm(rom.cellU * aProj - Us[i], wU) / peakU;
        double alphaProj = 0;
        if (rom.alpha)
            alphaProj = weightedNorm(rom.alphaLift + rom.alpha->reconstruct(rom.alpha->project(as - rom.alphaLift)) - as, m.V) /
                        weightedNorm(as, m.V);
        rows.push_back({{"t", times[i]},
                        {"trained", trained},
                        {"alpha_error", aErr},
                        {"alpha_projection_error", alphaProj},
                        {"u_error", uErr},
                        {"u_projection_error", uProj},
                        {"runout_star", rom.shape.runoutStar(m, ar)},
                        {"runout_star_full", rom.shape.runoutStar(m, as)},
                        {"height_star", rom.shape.heightStar(m, ar)},
                        {"height_star_full", rom.shape.heightStar(m, as)},
                        {"pressure_error", pModelAt[i]},
                        {"lithostatic_pressure_error", pErrAt[i]},
                        {"kinetic_energy_j", tr.kineticEnergy[i]},
                        {"powder_volume_m3", tr.powderVolume[i]}});
        aSum += aErr;
        uSum += uErr;
        aProjSum += alphaProj;
        uProjSum += uProj;
        aMax = std::max(aMax, aErr);
        uMax = std::max(uMax, uErr);
        if (!trained) {
            aHold += aErr;
            uHold += uErr;
            ++held;
        }
    }
    const auto& last = rows.back();
    const double n = static_cast<double>(rows.size());
    const double Lr = last["runout_star"], Lf = last["runout_star_full"], Hr = last["height_star"],
                 Hf = last["height_star_full"];
    return {{"snapshots", f.path().string()},
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
            {"lithostatic_pressure_error", pErr / n},
            {"lithostatic_viscosity_error", nuErr / n},
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
}

nlohmann::json predictCollapse(const CollapseGalerkin& built, double muS, double muD, double i0, double endTstar,
                               int perTstar) {
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
    return {{"mu_s", muS},
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
}

}  // namespace mixload::rom
