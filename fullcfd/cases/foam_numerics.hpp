// SPDX-License-Identifier: GPL-3.0-or-later
// Numerics shared by mixload's interFoam cases.
#pragma once
#include <string>

namespace mixload::cases {
std::string interFoamSchemes();
std::string interFoamSolution(const std::string& alphaName);
std::string decomposeParDict(int np);
// The libs entry for controlDict: absolute paths of mixload's OpenFOAM libraries.
std::string mixloadFoamLibs();
std::string rheologyLibraryPath();
std::string monitorsLibraryPath();
}  // namespace mixload::cases
