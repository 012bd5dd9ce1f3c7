// SPDX-License-Identifier: GPL-3.0-or-later
// The POD-Galerkin collapse model as a file (`mixload rom build` writes it, `rom run` and `rom check`
// read it): HDF5, schema "mixload-rom-collapse", written to a temporary name and renamed. It carries
// the case it was built for (/mesh and /params copied from the first training file), so it is used
// without the training snapshots.
//
//   /             attributes: schema, schema_version, mixload_version, git_commit, created_utc,
//                 mesh_fingerprint, options (JSON: the build options), sources (JSON: each training
//                 file with its scene hash, times and mu(I) coefficients), train_times, build_seconds
//   /mesh, /params   as in a snapshot file
//   /flow         the flow basis (rom/pod_model's basis datasets: modes [K x faces], weights, ...)
//   /cell_velocity [K x 3 cells]   each mode's reconstructed cell velocity
//   /alpha, /alpha_lift            the powder-fraction basis and lift (reduced alpha only)
#pragma once

#include <filesystem>

#include "rom/galerkin/collapse_galerkin.hpp"

namespace mixload::rom {

inline constexpr const char* kCollapseModelSchema = "mixload-rom-collapse";
inline constexpr int kCollapseModelSchemaVersion = 1;

void writeCollapseModel(const CollapseGalerkin& model, const store::CaseFile& source, const std::filesystem::path& file);
// Throws InputError naming the file for anything but a complete model file of this version.
CollapseGalerkin readCollapseModel(const std::filesystem::path& file);

// A model's fields (alpha and the reconstructed U at each time of a trajectory) as a snapshot file
// (schema mixload-snapshots 1: no boundary values) with its XDMF beside it, the mesh and params
// copied from the model file: ParaView and every snapshot reader take it as they take a full run's.
void writeCollapseFields(const CollapseGalerkin& model, const std::filesystem::path& modelFile,
                         const CollapseTrajectory& trajectory, const std::filesystem::path& file);

}  // namespace mixload::rom
