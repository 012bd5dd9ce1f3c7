// SPDX-License-Identifier: GPL-3.0-or-later
// How many core-hours a mixer campaign's open points still need: an estimate from the campaign's
// own finished runs, so that a driver's slices (and a session's cores) can be planned. A point's
// cost is its flow to a steady verdict times the core-seconds a second of flow costs. The steady
// test compares windows of half a residence time (M / feed), so the flow to a verdict grows with
// the residence time; its fit on the finished runs, t = a + b M / feed, says how. M at an open
// point comes from the kriging model that places warm starts and adaptive points.
#pragma once
#include <map>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "campaign/warm_start.hpp"
#include "doe/parameter_space.hpp"
#include "store/ledger.hpp"

namespace mixload::experiments {

// What a mixer point costs, fitted on steady runs: the flow to a verdict against the residence
// time M / feed, and the median core-seconds per second of flow.
struct RunCost {
    double intercept = 0;       // a in t = max(a + b tau, floor) [s]
    double perResidence = 0;    // b
    double floor = 0;           // the fastest verdict seen [s]
    double rate = 0;            // core-seconds per second of flow
    double medianAbsError = 0;  // of t on the runs fitted, relative
    size_t runs = 0;
    double flowToVerdict(double residenceS) const;
    // A point at loading M [kg] and feed [kg/h] that has run flowDone seconds already.
    double coreHours(double loadingKg, double feedKgH, double flowDoneS = 0) const;
};

// The fit on the campaign's steady runs and the pool's; none with fewer than five to fit.
std::optional<RunCost> fitRunCost(const store::CampaignInfo& c, const std::vector<store::LedgerRun>& runs,
                                  const std::vector<WarmRun>& pool);

// runs: the campaign's rows; pool: finished runs of campaigns on the same base scene that join the
// fits (a hold-out campaign forecast from its training campaign's runs); flowDone: flow already
// run on an unfinished point [s], by design index. Returns null when fewer than five steady runs
// are at hand (no fit to trust), else {points: [...], core_hours_left, ...} with the fit's own
// error on the runs it was fitted to.
nlohmann::json forecastCampaign(const store::CampaignInfo& c, const std::vector<store::LedgerRun>& runs,
                                const ParameterSpace& space, const std::vector<WarmRun>& pool,
                                const std::map<int, double>& flowDone);

}  // namespace mixload::experiments
