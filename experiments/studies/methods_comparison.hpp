// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace mixload::experiments {

// The paper's MRF-versus-sliding-mesh comparison (its Table 3: MRF 14-18% below SM) from a mixer
// study's rows: one entry per operating point (mesh, rpm, feed, start) that has both an mrf and an
// sm row, with both loadings, the difference (M_mrf - M_sm) / M_sm, whether both are results
// (steady, powder conserved), and each method's cost: wall seconds per simulated second and wall
// seconds to its verdict. Points without both methods are left out.
nlohmann::json compareMethods(const nlohmann::json& rows);

// Writes <out>/methods.md, methods.csv and methods.png (M of both methods against feed, and the
// difference against feed with the paper's band) for compareMethods' entries. Returns the plot's
// warning ("" when drawn).
std::string writeMethodsComparison(const std::filesystem::path& out, const nlohmann::json& pairs);

}  // namespace mixload::experiments
