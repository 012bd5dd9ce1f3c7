// SPDX-License-Identifier: GPL-3.0-or-later
// The powder a flow holds once it has carried the feed long enough: the steady powder fraction of a
// fixed, conservative face flux, and that flux rebuilt from cell velocities. A reduced steady model
// of the mixer keeps alpha on the mesh and takes the flow from a regression (issue 15); these are
// its two steps, and what `mixload rom steady` checks them with on a full run's own fields.
//
// The loading of a steady mixer is a residence time: M = rho Q tau, set by the slow axial flux
// through the bed, which is about 1e-2 of the rotor's tangential flux there. Small errors in the
// flux therefore move M a lot (docs/reduced-models.md, "A reduced steady model of the mixer").
#pragma once
#include <map>
#include <string>
#include <vector>

#include "rom/operators/fv_mesh.hpp"
#include "store/case_file.hpp"

namespace mixload::rom {

struct SteadyPowder {
    Eigen::VectorXd alpha;
    double inflow = 0, outflow = 0;  // powder volume through the boundary, m^3/s
    double residual = 0;             // of the linear solve, relative
};

// The pseudo-time step in fills of the domain by the powder's inflow: long enough that the powder still
// accumulating in it is a 1e-3 share of the inflow's, short enough to keep the upwind matrix well
// conditioned where closed recirculations make it nearly singular.
inline constexpr double kSteadyFillTimes = 1e3;

// First-order upwind, implicit, from an empty domain with one pseudo-time step of
// kSteadyFillTimes times the domain's volume over the inflow: the steady solution wherever the inflow reaches, and zero in
// closed recirculations (which a steady transport cannot fill). inflowFraction: the fraction
// entering through each named patch's inflow faces; other inflow faces bring none. The flux must
// be divergence-free (the outflow then equals the inflow to the solver's round-off).
SteadyPowder steadyPowder(const FvMesh& m, const Eigen::VectorXd& flux, const std::map<std::string, double>& inflowFraction);

// The flux the solver carries the powder with, rebuilt from the cell velocity and the stored
// boundary values: linear face interpolation, made relative to the rotor on every face of an MRF
// zone's cells (as MRF's makeRelative does), then made divergence-free by the smallest correction
// (a Poisson equation for a potential that is zero on the open patch's faces).
Eigen::VectorXd fluxFromVelocity(const FvMesh& m, const Vectors& U, const Vectors& boundaryU,
                                 const std::vector<store::CaseFile::MrfZone>& zones, const std::string& openPatch);

}  // namespace mixload::rom
