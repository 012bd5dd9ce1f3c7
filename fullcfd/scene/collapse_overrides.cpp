// SPDX-License-Identifier: GPL-3.0-or-later
#include "scene/collapse_overrides.hpp"

namespace mixload::scene {

CollapseScene CollapseOverrides::scene() const {
    CollapseScene s;
    s.material = loadMaterial(material);
    if (muS) s.material.muS = *muS;
    if (muD) s.material.muD = *muD;
    if (I0) s.material.I0 = *I0;
    s.aspect = aspect;
    s.length = length;
    s.cellsPerLength = cellsPerLength;
    s.rheology = rheology;
    s.convention = convention;
    s.etaMax = etaMax;
    s.capHeightRatio = capHeightRatio;
    s.maxCourant = maxCourant;
    s.restFraction = restFraction;
    s.capTstar = capTstar;
    s.writesPerTstar = writesPerTstar;
    s.validate();
    return s;
}

}  // namespace mixload::scene
