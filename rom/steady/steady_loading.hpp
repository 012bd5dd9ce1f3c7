// SPDX-License-Identifier: GPL-3.0-or-later
// The steady transport checked on a full mixer run's own fields: at each stored time, the loading
// the run holds (rho sum alpha V) beside the loading its flow would hold at steady state, from the
// solver's own flux (phi) and from the flux rebuilt from its cell velocity. This is what decides
// whether a reduced steady model can take its flow from a velocity regression (issue 15).
#pragma once
#include <nlohmann/json.hpp>

#include "store/snapshot_file.hpp"

namespace mixload::rom {

// every: every k-th stored time (the last one always). Throws InputError for a file that is not a
// mixer run or holds neither phi nor U with boundary values.
nlohmann::json steadyLoadingCheck(const store::SnapshotFile& f, int every);

}  // namespace mixload::rom
