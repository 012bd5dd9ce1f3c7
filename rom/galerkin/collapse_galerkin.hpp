// SPDX-License-Identifier: GPL-3.0-or-later
// A POD-Galerkin reduced model of the granular column collapse (VOF, mu(I) powder and air).
//
// The flow is reduced in its face fluxes, not its cell velocities: phi = |Sf| Psi a, with Psi the
// POD modes of the stored fluxes' normal velocities. Every stored flux is discretely
// divergence-free, so every mode is, and the momentum equation written per face and projected on
// the modes in the density-weighted face product loses its pressure term exactly (a discrete
// summation by parts leaves only the open boundary, where p_rgh = 0): no pressure modes, no
// supremizers, no Poisson equation. What drives the collapse is the projected gravity term
// -gh grad(rho), whose projection is the power of gravity on the reduced flow. The cell velocity
// each mode carries is OpenFOAM's reconstruct of its flux.
//
// Projected per face f and mode k, with V_f = |Sf| / deltaCoeff_f:
//   sum_j [sum_f V_f rho_f Psi_fk Psi_fj] da_j/dt
//     = sum_f V_f Psi_fk n_f . interp(-rho (U.grad)U + div(mu (grad U + dev2 grad U^T)))_f
//       - sum_f |Sf| Psi_fk gh_f (rho_N - rho_O)
// The mu(I) law needs the pressure, which the projection removed: the model closes it (below,
// PressureClosure), and the check measures the closure's error against the stored pressure. The
// equations themselves are in collapse_flow; checks and predictions in collapse_check.
//
// The powder fraction is either kept on the mesh and carried by the reduced flux (van Leer with
// interFoam's interface compression, explicit), or reduced itself (alpha = alpha_0 + X b, the same
// update projected on X).
// Time: alpha and the flow alternate in steps of the transport's Courant limit; within each, the
// flow's stiff ODE (the capped viscosity) goes to CVODE's BDF. The model watches its kinetic energy
// against the potential energy the column can release, and its powder volume, and stops with an
// error naming which one failed instead of running on.
#pragma once

#include <functional>
#include <optional>

#include <nlohmann/json.hpp>

#include "rom/galerkin/collapse_hyper.hpp"
#include "rom/galerkin/collapse_shape.hpp"
#include "rom/operators/fv_mesh.hpp"
#include "rom/operators/granular_viscosity.hpp"
#include "rom/pod/pod.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::rom {

// The pressure the mu(I) law reads, which the projection removed from the flow equations: the
// lithostatic weight of the powder above (the default), or recovered from the reduced momentum (the
// part of its unbalanced face momentum that is a pressure gradient: a Poisson equation on the mesh
// per step). The recovered one is the closer pressure (8% against 23% in the powder) but gave the
// worse runout on two of three tests: the truncated flow lacks friction in thin flowing layers, which
// the lithostatic pressure's overestimate makes up (README, "POD-Galerkin").
enum class PressureClosure { recovered, lithostatic };

struct CollapseGalerkinOptions {
    PressureClosure pressure = PressureClosure::lithostatic;
    int modes = 0;                // flow modes (0: by energy)
    double energy = 0.9999;       // share of the flow's (density-weighted) energy the modes keep
    bool reducedAlpha = false;    // reduce alpha too (else it is carried on the mesh)
    int alphaModes = 0;           // 0: by alphaEnergy
    double alphaEnergy = 0.99999;
    int hyperPoints = 0;          // hyper-reduce the mu(I) viscous term at at most this many cells (0: on the whole mesh)
    HyperMethod hyperMethod = HyperMethod::ecsw;
    double hyperTolerance = 0.003; // ECSW: stop adding cells once the term's training error is this small (0.01 left the velocity 50% further off)
    bool hyperConvection = false; // hyper-reduce the convection too (ECSW, same points cap and tolerance)
    int trainEvery = 1;           // train on every k-th stored time (the rest are held out)
    // The step and tolerance: against the model integrated tightly (Courant 0.1, 0.005 t*, rtol 1e-5)
    // these move L*f by 0.07-0.2% and H*f by about 0.1% on the benchmark's four held-out runs, a
    // twentieth of the model's own error, at a third of the cost of (0.3, 0.01 t*, 3e-3).
    double courant = 0.5;         // of the transport step (the van Leer bound)
    double cAlpha = 1;            // interface compression (the case's cAlpha)
    double maxStepTstar = 0.04;   // largest step, in t*
    double rtol = 3e-2;           // CVODE's relative tolerance
    bool restartEachStep = false; // restart CVODE after each alpha step (else it carries its history on)
    double massTolerance = 0.01;  // stop when the powder volume drifts by more than this share
    // Diagnosis only (reproduceCollapse): the mu(I) law reads the solver's stored pressure,
    // interpolated in time, instead of the lithostatic closure; isolates the closure's effect.
    bool storedPressure = false;
    // Diagnosis only: alpha is carried by the solver's stored flux (no reduced flow), which isolates
    // the transport's own error.
    bool storedFlux = false;
};

// A failure of the reduced model itself (energy or mass out of bounds, the integrator stuck):
// reported with what failed, never a result.
struct RomFailure : std::runtime_error {
    using std::runtime_error::runtime_error;
};

struct CollapseGalerkin {
    enum class Wall { noSlip, slip, open };

    FvMesh mesh;
    GranularLaw law;
    double airRho = 0, airNu = 0, gravity = 0, tStar = 0;
    CollapseShape shape;
    std::vector<Wall> walls;      // per boundary face
    PodBasis flow;                // face normal velocities (flux / |Sf|)
    Eigen::MatrixXd cellU;        // 3 cells x modes: each mode's reconstructed cell velocity (row-major)
    std::optional<PodBasis> alpha;
    Eigen::VectorXd alphaLift;    // alpha = alphaLift + X b (reduced alpha)
    std::optional<ViscousHyper> hyper;  // the mu(I) viscous term at a few cells (collapse_hyper)
    std::optional<ConvectionHyper> convectionHyper;  // the convection at a few cells
    CollapseGalerkinOptions options;
    std::string meshFingerprint;
    std::vector<std::string> trainFiles;
    nlohmann::json sources = nlohmann::json::array();  // per training file: path, scene hash, times, mu(I)
    size_t trainTimes = 0;        // snapshots the bases were built from, over all files
    double buildSeconds = 0;

    // From the snapshots of one or more collapse runs on one mesh (other mu(I) coefficients: a
    // parametric model). The law is the first file's until a check replaces it.
    static CollapseGalerkin build(const std::vector<store::SnapshotFile>& files, const CollapseGalerkinOptions& options);
    // The case's parts (mesh, law, air, gravity, shape, walls) from a snapshot or model file, no bases.
    static CollapseGalerkin fromCase(const store::CaseFile& f);
    int modes() const { return static_cast<int>(flow.modes.cols()); }
};

struct CollapseTrajectory {
    std::vector<double> times;
    std::vector<Eigen::VectorXd> alpha, flow;  // per output time: alpha on the mesh, flow coefficients
    std::vector<Eigen::VectorXd> pressure;     // per output time: the pressure the mu(I) law read
    std::vector<double> kineticEnergy, powderVolume;
    long steps = 0, odeSteps = 0, rhsEvaluations = 0, jacobianEvaluations = 0;
    double clippedVolume = 0;                  // alpha clipped back into [0, 1] (kept-alpha model)
    double wallSeconds = 0;
};

// Runs the model from (alpha0, the flux phi0) at t0 through every output time (increasing, > t0).
// The diagnoses' stand-ins: either, when given, replaces the model's own pressure or flux.
struct StoredFields {
    std::function<Eigen::VectorXd(double t)> pressure, flux;
};
CollapseTrajectory runCollapseGalerkin(const CollapseGalerkin& rom, const Eigen::VectorXd& alpha0,
                                       const Eigen::VectorXd& phi0, double t0, const std::vector<double>& outputs,
                                       const StoredFields& stored = {});

}  // namespace mixload::rom
