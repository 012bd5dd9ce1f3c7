// SPDX-License-Identifier: GPL-3.0-or-later
// A POD basis of stored snapshots, and its file: `mixload rom pod` builds it, reduced models and
// POD regression read it. The file is HDF5 (schema "mixload-pod", below), written to a temporary
// name and renamed, so a file under its final name is complete.
//
//   /                attributes: schema, schema_version, mixload_version, git_commit, created_utc,
//                    mesh_fingerprint, fields (comma-separated), sources (JSON: file, scene hash,
//                    times), energy_target, energy_kept, subtract_mean
//   /weights [R]     cell volume per row (over its field's energy when coupled)
//   /field_scales [F], /components [F]
//   /mean [R], /modes [K x R], /eigenvalues [N], /coefficients [N x K]
// R rows: the fields one after the other, a vector field's components together per cell.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rom/pod/pod.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::rom {

inline constexpr const char* kPodSchema = "mixload-pod";
inline constexpr int kPodSchemaVersion = 1;

struct PodModel {
    PodBasis basis;
    std::vector<std::string> fields;  // as asked: alpha, U, p, ...
    std::vector<int> components;      // per field
    size_t cells = 0;
    std::string meshFingerprint;
    nlohmann::json sources = nlohmann::json::array();
    double energyTarget = 0;
    nlohmann::json provenance;         // read back from a file

    // Row where each field starts.
    std::vector<Eigen::Index> fieldStarts() const;
};

// One snapshot file's fields stacked into the model's rows.
Eigen::MatrixXd stackedFields(const store::SnapshotFile& f, const std::vector<std::string>& fields);

// POD of the given fields (one: per field; several: coupled) over every stored time of the set.
// Throws InputError for an unknown field.
PodModel buildPod(const store::SnapshotSet& set, const std::vector<std::string>& fields, const PodOptions& options);

// A basis's datasets (weights, field_scales, mean, modes, eigenvalues, coefficients) in a file or
// group, as the POD file holds them; reduced-model files store their bases the same way.
void writeBasis(hid_t loc, const PodBasis& b);
PodBasis readBasis(hid_t loc);

void writePod(const PodModel& m, const std::filesystem::path& file);
// Throws InputError naming the file for anything but a complete POD file of this schema version.
PodModel readPod(const std::filesystem::path& file);

}  // namespace mixload::rom
