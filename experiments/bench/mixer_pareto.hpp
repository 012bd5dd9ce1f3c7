// SPDX-License-Identifier: GPL-3.0-or-later
// Time against error for the mixer loading (issue 19's mixer half; issue 15's mixer benchmark): on
// the steady runs of a hold-out campaign (placed by design, never used to fit), each method's time
// per answer and error in M. The reference is the hold-out's own full run; the same points on
// coarser meshes (campaigns of the same design) are the full model's cheaper answers; the loading
// surrogate (kriging and response surface, exact similarity, the nugget at or above the training
// campaign's replicate noise when it has replicates) and the POD regression (of alpha and
// of ln alpha) are fitted on a training campaign on the reference mesh. Full runs are costed in
// core-seconds from their ledgers; the models are timed here, in this process.
#pragma once
#include <filesystem>
#include <vector>

#include <nlohmann/json.hpp>

#include "campaign/campaign.hpp"

namespace mixload::experiments {

struct MixerPareto {
    CampaignPlace train, holdout;
    std::vector<CampaignPlace> coarse;  // the hold-out's design on coarser meshes (may be empty)
    std::filesystem::path out = "runs/bench-mixer-pareto";
};

// Writes <out>/runs.md and .csv (per hold-out run, every method's M and error) and the Pareto files
// (bench/pareto). Throws InputError for campaigns that are not mixer campaigns, a coarse campaign
// whose design differs from the hold-out's, or fewer than 5 steady training runs or 1 hold-out run.
nlohmann::json runMixerPareto(const MixerPareto& bench);

}  // namespace mixload::experiments
