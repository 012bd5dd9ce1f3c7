// SPDX-License-Identifier: GPL-3.0-or-later
// The powder's mu(I) kinematic viscosity as mixload's OpenFOAM viscosity model computes it
// (fullcfd/rheology: the same muILaw.H), from a shear rate and a pressure field: the nonlinear term
// the reduced models must evaluate (and hyper-reduce). Coefficients come from the snapshot file,
// exactly as the solver read them.
#pragma once
#include <string>

#include <Eigen/Dense>

#include "muILaw.H"
#include "store/snapshot_file.hpp"

namespace mixload::rom {

struct GranularLaw {
    rheology::MuIParams law{};
    double rho = 0, d = 0, rhoS = 0, etaMax = 0, pMin = 0;

    // Throws InputError for a file without coefficients or a model other than muI.
    static GranularLaw fromCase(const store::CaseFile& f);
    // nu = min(mu(I) max(p, pMin) / gammaDot, etaMax) / rho, cell by cell.
    Eigen::VectorXd nu(const Eigen::VectorXd& strainRate, const Eigen::VectorXd& p) const;
    // d nu / d gammaDot at the same shear rates and pressures (0 where the cap holds): what a
    // reduced model's Jacobian needs.
    Eigen::VectorXd dNuDStrainRate(const Eigen::VectorXd& strainRate, const Eigen::VectorXd& p) const;
};

}  // namespace mixload::rom
