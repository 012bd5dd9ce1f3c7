// SPDX-License-Identifier: GPL-3.0-or-later
// Snapshots: one HDF5 file per run (schema in README, "Snapshots") with an XDMF sidecar for
// ParaView. Written to a temporary name and renamed, so a file under the final name is complete.
// Reading them is store/snapshot_file.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mixload::post {

struct SnapshotExport {
    std::filesystem::path runDir;
    std::filesystem::path output;             // empty: <runDir>/snapshots.h5
    int every = 1;                            // every K-th written time
    std::vector<std::string> fields{"alpha", "U", "p"};  // "alpha" means alpha.powder
    bool float64 = false;                     // fields in float64 instead of float32
};

// Exports and returns a summary (file, xdmf, times, cells, fields, bytes). Throws InputError for
// bad arguments or a directory that is not a run, before anything is written.
nlohmann::json exportSnapshots(const SnapshotExport& e);

}  // namespace mixload::post
