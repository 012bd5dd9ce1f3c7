// SPDX-License-Identifier: GPL-3.0-or-later
#include "scene/mixer_overrides.hpp"

#include "common/input_error.hpp"

namespace mixload::scene {

MixerScene MixerOverrides::build(const SceneKeys& keys) const {
    SceneKeys all;
    for (const auto& a : sets) parseSceneKey(a, all);
    for (const auto& [k, v] : keys) all[k] = v;
    MixerScene s = loadMixerScene(scene, all);
    if (method) s.method = *method;
    if (mesh) s.setMesh(*mesh);
    if (cellSize) {
        if (mesh) throw InputError("cell-size", formatNumber(*cellSize), "either --mesh or --cell-size, not both");
        s.mesh = "custom";
        s.cellSize = *cellSize;
    }
    if (mesher) s.mesher = *mesher;
    if (rpm) s.rpm = *rpm;
    if (feedKgH) s.feedKgH = *feedKgH;
    if (muS) s.material.muS = *muS;
    if (muD) s.material.muD = *muD;
    if (I0) s.material.I0 = *I0;
    if (d) s.material.grainDiameter = *d;
    if (rho) {
        requireRange("rho", *rho, 0.0, 20000.0, false, true);
        s.material.grainDensity = *rho / s.material.solidFraction;
    }
    if (muS || muD || I0 || d || rho) s.material.name += "-modified";
    if (rheology) s.rheology = *rheology;
    if (convention) s.convention = *convention;
    if (etaMax) s.etaMax = *etaMax;
    if (initialLoadingKg) s.initialLoadingKg = *initialLoadingKg;
    if (endTime) s.endTime = *endTime;
    if (ltsIterations) s.ltsIterations = *ltsIterations;
    if (window) s.steadyWindowRevs = *window;
    if (residence) s.steadyResidence = *residence;
    if (tol) s.steadyTol = *tol;
    if (flowTol) s.steadyFlowTol = *flowTol;
    if (minTime) s.minTime = *minTime;
    if (numerics) s.numerics = MixerNumerics::named(*numerics);
    if (airViscosity) s.numerics.airViscosity = *airViscosity;
    if (courantAlphaMin) s.numerics.courantAlphaMin = *courantAlphaMin;
    if (nonOrthCorrectors) s.numerics.nonOrthCorrectors = *nonOrthCorrectors;
    if (maxDeltaT) s.numerics.maxDeltaT = *maxDeltaT;
    if (maxCourant) s.maxCourant = *maxCourant;
    if (alphaSubCycles) s.numerics.alphaSubCycles = *alphaSubCycles;
    s.validate();
    return s;
}

}  // namespace mixload::scene
