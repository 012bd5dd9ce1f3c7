// SPDX-License-Identifier: GPL-3.0-or-later
// The final fields of a campaign's runs, kept beside its ledger so that they outlive the run
// directories (a machine that comes back without them; a ledger shipped in data/). One snapshot
// file, <campaign dir>/fields.h5: the mesh once and, per kept run, its last stored powder fraction
// and velocity as one column each (its "time" is the run's index in the design; the velocity is NaN
// for a run kept before velocities were, whose directory is gone). Measured on the CI test's 1 cm
// gcm250 campaign (5 929 cells): 0.68 MB for three runs, of which the mesh is 0.56 MB and each run
// 0.02 MB, against a few MB for a run's own snapshots.h5.
#pragma once
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "store/ledger.hpp"

namespace mixload::store {

std::filesystem::path campaignFieldsFile(const std::filesystem::path& ledger);

// Adds every finished run with <run dir>/snapshots.h5 that the kept file does not hold yet (the
// file is rewritten whole, atomically). Returns {file, kept, added}. Throws InputError when there is
// nothing to keep, or a run's mesh differs from the kept ones.
nlohmann::json keepCampaignFields(const std::filesystem::path& ledger, const std::string& campaign);

// The design indices of the runs the campaign's kept fields file holds (none without the file).
std::set<int> keptRunIndices(const std::filesystem::path& ledger);

// One kept run's final fields as a field file of its own (the powder fraction, and the velocity
// when kept, at the run's final time): a warm start for a point whose source run directory is gone.
// Written whole and atomically. False when the kept file does not hold the run.
bool writeKeptRunFields(const std::filesystem::path& ledger, int index, const std::filesystem::path& file);

struct FinalField {
    LedgerRun run;
    Eigen::VectorXd alpha;     // the last stored powder fraction, one value per cell
    Eigen::VectorXd U;         // the velocity at the same time, 3 per cell; empty when not kept
    double bulkDensity = 0;    // [kg/m3] (mixer runs; 0 for a collapse)
    // The powder fraction averaged over the stored times of the run's final window (the steady
    // test's, which its loading_kg averages), when the run directory's snapshots hold three or more
    // of them; else empty. A steady mixer still churns: how far the last field lies from this
    // mean is the field's own fluctuation: a steady prediction compared with one instant is off by
    // about that much however good it is.
    Eigen::VectorXd alphaWindowMean;
    int windowTimes = 0;
};

struct FinalFields {
    std::vector<FinalField> runs;            // finished runs in design order
    std::filesystem::path meshSource;        // a snapshot file with the shared mesh and the scene's params
};

// Every finished run's final powder fraction: from <run dir>/snapshots.h5, or from the kept file
// when the run directory is gone. Throws InputError naming the campaign when no finished run has
// either, and when files of different meshes meet.
FinalFields campaignFinalFields(const std::filesystem::path& ledger, const std::string& campaign);

}  // namespace mixload::store
