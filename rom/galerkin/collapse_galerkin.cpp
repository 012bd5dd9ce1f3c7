// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/galerkin/collapse_galerkin.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "rom/operators/alpha_transport.hpp"
#include "rom/galerkin/collapse_flow.hpp"
#include "rom/galerkin/cvode_integrator.hpp"
#include "rom/operators/fv_operators.hpp"

namespace mixload::rom {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

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

CollapseGalerkin CollapseGalerkin::build(const std::vector<store::SnapshotFile>& files, const CollapseGalerkinOptions& o) {
    const auto t0 = Clock::now();
    if (files.empty()) throw InputError("FILES", "(none)", "one or more collapse snapshot files");
    if (o.trainEvery < 1) throw InputError("train-every", std::to_string(o.trainEvery), "1 or more");
    if (o.modes < 0) throw InputError("modes", std::to_string(o.modes), "0 (by energy) or more");
    if (o.hyperPoints < 0) throw InputError("hyper-points", std::to_string(o.hyperPoints), "0 (no hyper-reduction) or more");
    if (o.hyperConvection && (o.hyperPoints == 0 || o.hyperMethod != HyperMethod::ecsw))
        throw InputError("hyper-convection", "on", "with --hyper-points and --hyper ecsw");
    const store::SnapshotFile& first = files.front();
    for (const auto& f : files)
        if (f.meshFingerprint() != first.meshFingerprint())
            throw InputError("snapshot file", f.path().string(), "runs on one mesh (the same aspect ratio and cells as " +
                                                                       first.path().string() + ")");
    CollapseGalerkin r = fromCase(first);
    r.options = o;
    r.meshFingerprint = first.meshFingerprint();
    const auto& m = r.mesh;

    // Training columns: every k-th stored time of every file.
    std::vector<std::pair<const store::SnapshotFile*, size_t>> cols;
    for (const auto& f : files) {
        r.trainFiles.push_back(f.path().string());
        const auto t = f.powderTransport();
        r.sources.push_back({{"file", fs::absolute(f.path()).string()},
                             {"scene_hash", f.provenance().value("scene_hash", std::string())},
                             {"times", f.times().size()},
                             {"mu_s", t.value("muS", 0.0)},
                             {"mu_d", t.value("muD", 0.0)},
                             {"i0", t.value("I0", 0.0)}});
        for (size_t i = 0; i < f.times().size(); i += static_cast<size_t>(o.trainEvery)) cols.emplace_back(&f, i);
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
    if (o.hyperPoints > 0) {
        // The training viscosities as the model evaluates them: each run's own law, the stored
        // flux projected on the modes (the velocity the model can hold), and the default pressure
        // closure (lithostatic from alpha; the closure is a run option, and the recovered one has no
        // stored counterpart).
        const CollapseFlow flow(r);
        HyperTraining tr{Eigen::MatrixXd(m.cells, nCols), Eigen::MatrixXd(m.cells, nCols), Eigen::MatrixXd(r.flow.modes.cols(), nCols)};
        for (Eigen::Index k = 0; k < nCols; ++k) {
            const auto& [f, i] = cols[static_cast<size_t>(k)];
            const Frozen z = flow.freeze(f->column("alpha", i));
            tr.flow.col(k) = flow.project(z, f->faceColumn("phi", i));
            tr.rho.col(k) = z.rhoC;
            const Vectors U = flow.cellVelocity(tr.flow.col(k));
            tr.mu.col(k) = flow.mixtureViscosity(z.alpha, GranularLaw::fromCase(*f).nu(strainRate(m, U, flow.boundaryVelocity(U)), z.p));
        }
        r.hyper = buildViscousHyper(flow, tr, o.hyperMethod, o.hyperPoints, o.hyperTolerance);
        if (o.hyperConvection) r.convectionHyper = buildConvectionHyper(flow, tr, o.hyperPoints, o.hyperTolerance);
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
    CollapseFlow model(rom);
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
    if (model.hasJacobian())
        ode.setJacobian([&](double, const Eigen::VectorXd& y, Eigen::MatrixXd& J) { J = model.rateJacobian(*current, y); });

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
            z = model.freeze(alpha, &z);
            if (stored.pressure) model.setPressure(z, stored.pressure(t + dt));
            else if (o.pressure == PressureClosure::recovered) model.setPressure(z, model.recoverPressure(z, a));
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

}  // namespace mixload::rom
