// SPDX-License-Identifier: GPL-3.0-or-later
// Reading mixload snapshot files (schema in README, "Snapshots"): one file opened and checked once,
// and a set of files that share one mesh, read one file at a time so that a snapshot matrix never
// has to sit in memory whole. The writer is fullcfd/post/snapshots (it needs the OpenFOAM case).
#pragma once
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "store/case_file.hpp"
#include "store/h5_io.hpp"
#include "store/ledger.hpp"

namespace mixload::store {

inline constexpr const char* kSnapshotSchema = "mixload-snapshots";
// 2 adds /boundary/<field> (values on the non-empty patches' faces) and /faces/phi; 1 is still read.
inline constexpr int kSnapshotSchemaVersion = 2;

// "alpha" is the powder fraction, stored under OpenFOAM's name.
std::string storedFieldName(const std::string& field);

class SnapshotFile : public CaseFile {
public:
    // Checks schema, version and the groups every reader needs; throws InputError naming the file
    // (truncated, corrupt, another schema or version).
    explicit SnapshotFile(const std::filesystem::path& file);

    const std::vector<double>& times() const { return times_; }
    std::vector<std::string> fields() const;
    int components(const std::string& field) const;  // 1 (scalar) or 3 (vector)
    // One time as a column: cells (scalar) or 3 x cells, the components of a cell together.
    Eigen::VectorXd column(const std::string& field, size_t timeIndex) const;
    // The field's values on the non-empty patches' faces at one time (schema 2; InputError for a
    // file without them), components together per face.
    Eigen::VectorXd boundaryColumn(const std::string& field, size_t timeIndex) const;
    // A face field (phi): internal faces, then the non-empty patches' faces.
    Eigen::VectorXd faceColumn(const std::string& field, size_t timeIndex) const;
    bool hasFaceField(const std::string& field) const;
    // Cell centres at one time, x y z per cell: a moving mesh's (/fields/cell_centres), else the
    // fixed mesh's.
    std::vector<double> cellCentres(size_t timeIndex) const;
    // Every time (or the given ones) as columns.
    Eigen::MatrixXd matrix(const std::string& field, const std::vector<size_t>& timeIndices = {}) const;
    // Provenance, params, time range and every dataset's shape, type and stored size; verify reads
    // every dataset, so a corrupt chunk (checksum) is reported.
    nlohmann::json info(bool verify = true) const;

private:
    std::vector<double> times_;
};

// Fields that a model computed on a stored case's mesh, as a snapshot file (schema version 1: no
// boundary values) with its XDMF beside it: the mesh and params copied from `source`, `provenance`
// as root attributes (who wrote it, from what). fields: name -> cells x times (scalar) or
// 3 cells x times (vector, the components of a cell together). Written whole or not at all.
void writeDerivedSnapshots(const CaseFile& source, const std::vector<double>& times,
                           const std::vector<std::pair<std::string, Eigen::MatrixXd>>& fields,
                           const nlohmann::json& provenance, const std::filesystem::path& file);

// Snapshot files of one mesh, in order. Columns are numbered file by file, time by time.
class SnapshotSet {
public:
    // Throws InputError naming the first file whose mesh differs from the first file's.
    explicit SnapshotSet(const std::vector<std::filesystem::path>& files);

    size_t columns() const { return columns_; }
    size_t cells() const { return files_.front().cells(); }
    const Eigen::VectorXd& cellVolumes() const { return files_.front().cellVolumes(); }
    const std::vector<SnapshotFile>& files() const { return files_; }
    int components(const std::string& field) const { return files_.front().components(field); }
    // The field's columns of file i (one file in memory at a time).
    Eigen::MatrixXd block(const std::string& field, size_t i) const { return files_.at(i).matrix(field); }

private:
    std::vector<SnapshotFile> files_;
    size_t columns_ = 0;
};

// The snapshot files of a campaign's finished runs (<run dir>/snapshots.h5, in design order).
// Throws InputError when the ledger has no such campaign or none of its runs kept snapshots.
std::vector<std::filesystem::path> campaignSnapshotFiles(const std::filesystem::path& ledger,
                                                         const std::string& campaign);
// The same runs with their ledger rows (inputs, results, run directory).
std::vector<LedgerRun> campaignRunsWithSnapshots(const std::filesystem::path& ledger, const std::string& campaign);

}  // namespace mixload::store
