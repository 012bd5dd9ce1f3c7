// SPDX-License-Identifier: GPL-3.0-or-later
// What every mixload file that describes a stored case holds and every reader needs: the mesh
// (/mesh: cells, faces, patches), the scene's parameters (/params, with the powder's transport
// coefficients) and its provenance. Snapshot files and reduced-model files share it; a model file
// copies it from the snapshots it was built on, so it can be used without them.
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "store/h5_io.hpp"

namespace mixload::store {

// The attributes every mixload file opens with: schema, schema_version, mixload_version, git_commit
// and created_utc (what a reader checks, and where the file came from).
void writeFileHeader(hid_t file, const std::string& schema, int version);

class CaseFile {
public:
    // Opens the file and checks its schema attribute and version range and the mesh; throws
    // InputError naming the file (truncated, corrupt, another schema or version).
    CaseFile(const std::filesystem::path& file, const std::string& schema, int minVersion, int maxVersion);

    const std::filesystem::path& path() const { return path_; }
    int schemaVersion() const { return version_; }
    size_t cells() const { return static_cast<size_t>(volumes_.size()); }
    const Eigen::VectorXd& cellVolumes() const { return volumes_; }
    // Same cells, faces and volumes: files of one mesh (bitwise, as mixload writes them).
    const std::string& meshFingerprint() const { return fingerprint_; }
    nlohmann::json provenance() const;
    nlohmann::json params() const;  // every scene input (without the verbatim scene_json)
    // The powder's viscosity model and coefficients as the solver read them (InputError if the file
    // predates them).
    nlohmann::json powderTransport() const;

    struct Patch {
        std::string name, type;
        long long start = 0, size = 0;
    };
    std::vector<Patch> patches() const;
    // A frozen-rotor (MRF) zone as the solver read it: its cells, axis and speed. None for a case
    // without MRF or a file written before zones were kept.
    struct MrfZone {
        std::string name;
        std::vector<int32_t> cells;
        Eigen::Vector3d origin, axis;
        double omega = 0;  // rad/s
    };
    std::vector<MrfZone> mrfZones() const;
    std::vector<double> meshDoubles(const std::string& name) const;  // /mesh/<name>, flattened
    std::vector<int32_t> meshInts(const std::string& name) const;

    // Copies /mesh and /params into another open file.
    void copyCaseTo(hid_t file) const;

protected:
    std::filesystem::path path_;
    h5::Handle file_;
    int version_ = 0;

private:
    Eigen::VectorXd volumes_;
    std::string fingerprint_;
};

}  // namespace mixload::store
