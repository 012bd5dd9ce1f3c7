// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>

#include "scene/collapse_scene.hpp"

namespace mixload::cases {

// Name of the collapse monitor function object; its output lives in postProcessing/<name>/.
inline constexpr const char* kCollapseMonitor = "collapse";

// Writes a complete interFoam case for the scene into caseDir (which must exist).
void writeCollapseCase(const scene::CollapseScene& s, const std::filesystem::path& caseDir, int np);

// Area fraction of cell [x0,x1]x[y0,y1] covered by the column [0,Li]x[0,Hi]: the exact initial
// powder fraction, so the initial volume is Li*Hi*depth to round-off.
double columnOverlap(double x0, double x1, double y0, double y1, double Li, double Hi);

}  // namespace mixload::cases
