// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/operators/granular_viscosity.hpp"

#include <algorithm>
#include <stdexcept>

#include "common/input_error.hpp"

namespace mixload::rom {

GranularLaw GranularLaw::fromCase(const store::CaseFile& f) {
    const auto t = f.powderTransport();
    const std::string model = t.value("model", std::string());
    if (model != "muI")
        throw InputError("powder transport model", model, "muI (the reduced models evaluate this law only)");
    GranularLaw g;
    const auto get = [&](const char* k) {
        if (!t.contains(k)) throw InputError("powder transport", k, "a coefficient stored in " + f.path().string());
        return t[k].get<double>();
    };
    g.law = {get("muS"), get("muD"), get("I0")};
    g.rho = get("rho");
    g.d = get("d");
    g.rhoS = get("rhoS");
    g.etaMax = get("etaMax");
    g.pMin = get("pMin");
    return g;
}

Eigen::VectorXd GranularLaw::nu(const Eigen::VectorXd& sr, const Eigen::VectorXd& p) const {
    if (sr.size() != p.size()) throw std::invalid_argument("granular viscosity: shear rate and pressure sizes differ");
    Eigen::VectorXd out(sr.size());
    for (Eigen::Index c = 0; c < sr.size(); ++c) {
        // As granularViscosityModel::calcNu: the pressure clipped at pMin, the law of muI::mu.
        const double pc = std::max(p[c], pMin);
        const double mu = rheology::muOfI(law, rheology::inertialNumber(d, sr[c], pc, rhoS));
        out[c] = rheology::granularViscosity(mu, pc, sr[c], etaMax) / rho;
    }
    return out;
}

Eigen::VectorXd GranularLaw::dNuDStrainRate(const Eigen::VectorXd& sr, const Eigen::VectorXd& p) const {
    if (sr.size() != p.size()) throw std::invalid_argument("granular viscosity: shear rate and pressure sizes differ");
    Eigen::VectorXd out(sr.size());
    for (Eigen::Index c = 0; c < sr.size(); ++c) {
        const double pc = std::max(p[c], pMin);
        const double I = rheology::inertialNumber(d, sr[c], pc, rhoS);
        const double mu = rheology::muOfI(law, I);
        // eta = mu(I) p / gammaDot with I proportional to gammaDot: d eta / d gammaDot = p (I mu'(I) - mu) / gammaDot^2.
        const bool capped = !(sr[c] > 0) || mu * pc / sr[c] >= etaMax;
        out[c] = capped ? 0.0 : pc * (I * rheology::dMuDI(law, I) - mu) / (sr[c] * sr[c]) / rho;
    }
    return out;
}

}  // namespace mixload::rom
