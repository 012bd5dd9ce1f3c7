// SPDX-License-Identifier: GPL-3.0-or-later
// Numerics shared by mixload's interFoam cases.
#pragma once
#include <filesystem>
#include <string>

namespace mixload::cases {
std::string interFoamSchemes();
std::string interFoamSolution(const std::string& alphaName);
std::string decomposeParDict(int np);

// The powder phase as our rheology library reads it (friction values already in the case's
// convention), plus air. Shared by every scene.
struct PowderTransport {
    std::string rheology;  // muI | muIRegularised | schaeffer
    double bulkDensity, muS, muD, I0, grainDiameter, grainDensity, etaMax, pMin;
    double airViscosity = 1.5e-5;  // [m2/s]
};
std::string transportProperties(const PowderTransport& t);
// The libs entry for controlDict: absolute paths of mixload's OpenFOAM libraries.
std::string mixloadFoamLibs();
std::string rheologyLibraryPath();
std::string monitorsLibraryPath();
// A case names the libraries of the build that wrote it, by absolute path. A case resumed by another
// build (a study laid back on a machine whose build lives elsewhere) would fail to load them, so the
// solver's runner points the case's system/controlDict at this build's libraries before each slice.
// Returns whether the entry changed; a case without a controlDict or a libs entry is left alone.
bool refreshFoamLibs(const std::filesystem::path& caseDir);
}  // namespace mixload::cases
