// SPDX-License-Identifier: GPL-3.0-or-later
// The steady transport checked on a full mixer run's own fields: at each stored time, the loading
// the run holds (rho sum alpha V) beside the loading its flow would hold at steady state, from the
// solver's own flux (phi) and from the flux rebuilt from its cell velocity. This is what decides
// whether a reduced steady model can take its flow from a velocity regression (issue 15). The
// march (the solver's own explicit, compressive alpha transport on the run's mean flux, from its
// last state) asks the sharper question: does a frozen flux hold the run's bed at all?
#pragma once
#include <nlohmann/json.hpp>

#include "store/snapshot_file.hpp"

namespace mixload::rom {

struct SteadyCheckOptions {
    int every = 1;             // every k-th stored time (the last one always)
    int meanLast = 0;          // also the steady transport of phi averaged over the last k times
    double marchSeconds = 0;   // also march alpha from the last stored state on that mean flux
    double cAlpha = 1;         // the march's interface compression (the solver's cAlpha)
};

// Throws InputError for a file that is not a mixer run, holds neither phi nor U with boundary
// values, or options out of range (meanLast and the march need phi).
nlohmann::json steadyLoadingCheck(const store::SnapshotFile& f, const SteadyCheckOptions& o);

}  // namespace mixload::rom
