// SPDX-License-Identifier: GPL-3.0-or-later
// Issue 16's multi-fidelity pilot: the same formulation study on a fine and a coarse mesh, paired
// variant by variant. Co-kriging (Kennedy-O'Hagan) lets cheap coarse runs carry the fine ones only
// if the fine loading is a tight function of the coarse one; this says whether it is.
#pragma once
#include <filesystem>

#include <nlohmann/json.hpp>

namespace mixload::experiments {

// Reads <fine>/study.json and <coarse>/study.json (`mixload study formulation` output) and pairs the
// reference and every variant steady in both; or two campaign directories (<dir>/NAME/ledger.sqlite,
// the same design on two meshes) and pairs the design points steady in both whose inputs agree.
// Fits M_fine = a M_coarse + b, and writes
// fidelity.md, .csv and .png in out. Verdict: "earns its place" with at least 8 pairs and
// r^2 >= 0.9, "skip" below that r^2, "pilot too small" under 8 pairs. Throws InputError for a
// directory without a study.
nlohmann::json fidelityPilot(const std::filesystem::path& fine, const std::filesystem::path& coarse, const std::filesystem::path& out);

}  // namespace mixload::experiments
