// SPDX-License-Identifier: GPL-3.0-or-later
// Reads an OpenFOAM points file (polyMesh/points, ascii or binary) written by a real run.
#pragma once
#include <array>
#include <filesystem>
#include <vector>

namespace mixload::testing {

std::vector<std::array<double, 3>> readFoamPoints(const std::filesystem::path& file);

}  // namespace mixload::testing
