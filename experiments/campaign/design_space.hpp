// SPDX-License-Identifier: GPL-3.0-or-later
// A campaign's design space as its ledger records it, and where a run sits in it: what extending,
// replicating and warm-starting a campaign all measure distances in.
#pragma once
#include <string>
#include <vector>

#include "doe/parameter_space.hpp"
#include "store/ledger.hpp"

namespace mixload::experiments {

// The campaign's parameter space, from the ranges recorded in its ledger.
ParameterSpace rangesOf(const store::CampaignInfo& c, const std::string& name);

// A run's point in the design's unit cube.
std::vector<double> unitOf(const ParameterSpace& space, const store::LedgerRun& r);

double distance2(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace mixload::experiments
