// SPDX-License-Identifier: GPL-3.0-or-later
#include "app/collapse_options.hpp"

namespace mixload::app {

void CollapseOptions::add(CLI::App* cmd) {
    cmd->add_option("--material", material, "quartz|copper|avicel|glass_beads_jop or a material .toml")
        ->capture_default_str();
    cmd->add_option("--aspect", aspect, "Column aspect ratio a = Hi/Li, 0.2-10")->capture_default_str();
    cmd->add_option("--length", length, "Column length Li [m]")->capture_default_str();
    cmd->add_option("--cells-per-length", cellsPerLength, "Mesh: cells across Li (dx = Li/N)")
        ->capture_default_str();
    cmd->add_option("--mu-s", muS, "Override the material's mu_s");
    cmd->add_option("--mu-d", muD, "Override the material's mu_d (> mu_s)");
    cmd->add_option("--i0", I0, "Override the material's I0");
    cmd->add_option("--rheology", rheology, "muI|muIRegularised|schaeffer")->capture_default_str();
    cmd->add_option("--convention", convention,
                    "standard (eta = mu p / gammaDot) | paper (eta = mu p / (sqrt2 gammaDot))")
        ->capture_default_str();
    cmd->add_option("--eta-max", etaMax, "Viscosity cap [Pa s] (default: Rauter, rhoS/10 sqrt(g Hi^3))");
    cmd->add_option("--cap-h-ratio", capHeightRatio,
                    "Rauter's cap with H = this x Hi (a taller H: a stiffer cap, less creep of squat columns)")
        ->capture_default_str();
    cmd->add_option("--max-courant", maxCourant, "Flow and interface Courant limit of the time step")
        ->capture_default_str();
    cmd->add_option("--rest-fraction", restFraction,
                    "At rest when kinetic energy < this x its peak for 0.5 t*")
        ->capture_default_str();
    cmd->add_option("--writes-per-tstar", writesPerTstar,
                    "Written times per t* (more for reduced models' snapshots; 4 keeps the run's hash)")
        ->capture_default_str();
    cmd->add_option("--cap", capTstar, "End-time cap in t* (a run reaching it says stopped_by=cap)")
        ->capture_default_str();
}

}  // namespace mixload::app
