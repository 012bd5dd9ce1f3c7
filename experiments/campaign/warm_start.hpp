// SPDX-License-Identifier: GPL-3.0-or-later
// Where a mixer design point starts under --warm-nearest: the finished run of the campaign (or of
// the campaigns given with --warm-from-campaign) whose loading is nearest the point's predicted one.
#pragma once
#include <filesystem>
#include <vector>

#include "campaign/campaign.hpp"
#include "doe/parameter_space.hpp"
#include "store/ledger.hpp"

namespace mixload::experiments {

// A finished run of a campaign that may serve as a start, with the ledger whose kept fields hold
// it when its run directory is gone.
struct WarmRun {
    store::LedgerRun run;
    std::filesystem::path ledger;
};

// The finished runs of the campaigns `from` as starts for campaign c (InputError when one is on
// another base scene or mesh, or varies other inputs).
std::vector<WarmRun> warmPool(const store::CampaignInfo& c, const std::vector<CampaignPlace>& from);

// The start of point r of the campaign whose runs are `runs` and whose home is `home`: a run
// directory, a field file under <home>/warm, or empty (the deposit).
std::filesystem::path warmSourceFor(const std::vector<store::LedgerRun>& runs, const std::filesystem::path& home,
                                    const ParameterSpace& space, const store::LedgerRun& r,
                                    const std::vector<WarmRun>& pool = {});

}  // namespace mixload::experiments
