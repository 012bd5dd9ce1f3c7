// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/mixer_options.hpp"

#include "common/input_error.hpp"

namespace mixload::app {

void MixerOptions::add(CLI::App* cmd, bool withMethod) {
    cmd->add_option("--scene", scene, "Scene: a shipped scene (data/scenes) or a scene .toml file")
        ->capture_default_str();
    cmd->add_option("--set", sets,
                    "Set a numeric key of the scene file, TABLE.KEY=VALUE (e.g. "
                    "weir.chord_angle_deg=70, powder.eta_max_h_m=0.01); repeatable");
    if (withMethod)
        cmd->add_option("--method", method,
                        "mrf (frozen rotor, transient) | lts (MRF + local time stepping, "
                        "pseudo-steady) | sm (sliding mesh, AMI); default mrf");
    cmd->add_option("--mesh", mesh, "coarse | medium | fine (cell sizes in the scene file)");
    cmd->add_option("--mesher", mesher,
                    "ogrid (blockMesh O-grid, default) | snappy (castellated, mrf/lts only)");
    cmd->add_option("--cell-size", cellSize, "Explicit background cell size [m] (instead of --mesh)");
    cmd->add_option("--rpm", rpm, "Impeller speed [rev/min]");
    cmd->add_option("--feed-kg-h", feedKgH, "Powder feed rate [kg/h]");
    cmd->add_option("--mu-s", muS, "Override mu_s (in the scene's convention)");
    cmd->add_option("--mu-d", muD, "Override mu_d (> mu_s)");
    cmd->add_option("--i0", I0, "Override I0");
    cmd->add_option("--d", d, "Override the grain diameter d [m] (SI: 240e-6 for 240 um)");
    cmd->add_option("--rho", rho,
                    "Override the bulk density [kg/m3]; the grain density follows as rho / phi");
    cmd->add_option("--rheology", rheology, "muI | muIRegularised | schaeffer");
    cmd->add_option("--convention", convention, "standard | paper (see README)");
    cmd->add_option("--eta-max", etaMax, "Viscosity cap [Pa s] (default: Rauter with H = bore)");
    cmd->add_option("--initial-loading-kg", initialLoadingKg,
                    "Powder deposited uniformly at the bottom at t = 0 [kg]");
    cmd->add_option("--end-time", endTime, "Cap on simulated time [s] (mrf, sm); a sliding-mesh run that continues another (--warm-from an sm run of the same mesh and speed) counts it, and --min-time, from the source's time");
    cmd->add_option("--lts-iterations", ltsIterations, "Cap on pseudo-time iterations (lts)");
    cmd->add_option("--steady-window-revs", window,
                    "Steady test window [revolutions]: two consecutive windows compared");
    cmd->add_option("--steady-window-residence", residence,
                    "Steady test window: also at least this share of the residence time M/feed "
                    "(0: revolutions only; lts: ignored)");
    cmd->add_option("--steady-tol", tol, "Steady: window means agree within this fraction");
    cmd->add_option("--steady-flow-tol", flowTol,
                    "Steady: mean outflow within this fraction of the feed");
    cmd->add_option("--min-time", minTime, "No steady verdict before this time [s]");
    cmd->add_option("--numerics", numerics,
                    "Solver settings preset: fast (default) | legacy (every run before the "
                    "presets); the options below adjust either")
        ->group("Numerics");
    cmd->add_option("--air-viscosity", airViscosity, "Air kinematic viscosity [m2/s]")
        ->group("Numerics");
    cmd->add_option("--courant-alpha-min", courantAlphaMin,
                    "Courant limits count only cells with at least this powder fraction (0: all)")
        ->group("Numerics");
    cmd->add_option("--non-orth-correctors", nonOrthCorrectors,
                    "Pressure non-orthogonal correctors")
        ->group("Numerics");
    cmd->add_option("--alpha-sub-cycles", alphaSubCycles,
                    "MULES sub-cycles per step; the step's Courant limit is this many times the "
                    "alpha limit (1)")
        ->group("Numerics");
    cmd->add_option("--max-delta-t", maxDeltaT, "Largest time step [s] (also <= 1/72 revolution)")
        ->group("Numerics");
    cmd->add_option("--max-courant", maxCourant,
                    "Flow and interface Courant limit of the time step (1; the sliding mesh uses at "
                    "most 0.5)")
        ->group("Numerics");
}

}  // namespace mixload::app
