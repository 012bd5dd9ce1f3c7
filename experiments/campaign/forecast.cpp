// SPDX-License-Identifier: GPL-3.0-or-later
#include "campaign/forecast.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "campaign/campaign.hpp"
#include "campaign/design_space.hpp"
#include "campaign/progress.hpp"
#include "common/stats.hpp"
#include "doe/adaptive.hpp"

namespace mixload::experiments {

namespace {

// t = a + b x by least squares with a, b >= 0: a negative intercept or slope would forecast a
// negative flow for some point, so the fit falls back to the line through the origin or the mean.
std::pair<double, double> nonNegativeLine(const std::vector<double>& x, const std::vector<double>& t) {
    const double n = static_cast<double>(x.size());
    double sx = 0, st = 0, sxx = 0, sxt = 0;
    for (size_t i = 0; i < x.size(); ++i) sx += x[i], st += t[i], sxx += x[i] * x[i], sxt += x[i] * t[i];
    const double det = n * sxx - sx * sx;
    double a = det > 0 ? (sxx * st - sx * sxt) / det : st / n;
    double b = det > 0 ? (n * sxt - sx * st) / det : 0;
    if (b < 0) return {st / n, 0.0};
    if (a < 0) return {0.0, sxx > 0 ? sxt / sxx : 0.0};
    return {a, b};
}

}  // namespace

double RunCost::flowToVerdict(double residenceS) const {
    // The line has no floor where the residence time is short, but every run pays for its windows
    // and for leaving its start: no point is forecast faster than the fastest verdict seen.
    return std::max(intercept + perResidence * residenceS, floor);
}

double RunCost::coreHours(double loadingKg, double feedKgH, double flowDoneS) const {
    const double tau = loadingKg / feedKgH * 3600.0;
    return std::max(flowToVerdict(tau) - flowDoneS, 0.5 * tau) * rate / 3600.0;
}

namespace {

std::vector<const store::LedgerRun*> finishedOf(const std::vector<store::LedgerRun>& runs, const std::vector<WarmRun>& pool) {
    std::vector<const store::LedgerRun*> finished;
    for (const auto& r : runs) finished.push_back(&r);
    for (const auto& w : pool) finished.push_back(&w.run);
    return finished;
}

}  // namespace

std::optional<RunCost> fitRunCost(const store::CampaignInfo& c, const std::vector<store::LedgerRun>& runs,
                                  const std::vector<WarmRun>& pool) {
    // Every steady run counts, a replicate's start from a deposit being one way a point begins.
    std::vector<double> residence, flow, coreRate;
    for (const auto* r : finishedOf(runs, pool)) {
        const auto m = runQuantity(*r, "mixer");
        if (!m || !(*m > 0)) continue;
        // On the point: a run that continues kept progress has its verdict's time counted from its
        // own start, and its core-seconds from the point's first slice.
        const double inRun = r->result.value("steady_time_s", 0.0);
        if (!(inRun > 0)) continue;
        const double t = inRun + flowBefore(r->result.value("start", nlohmann::json()));
        residence.push_back(*m / mixerSceneFor(c.sceneJson, r->params).feedKgH * 3600.0);
        flow.push_back(t);
        if (r->coreSeconds && *r->coreSeconds > 0) coreRate.push_back(*r->coreSeconds / t);
    }
    if (flow.size() < 5 || coreRate.empty()) return std::nullopt;
    RunCost cost;
    std::tie(cost.intercept, cost.perResidence) = nonNegativeLine(residence, flow);
    cost.floor = *std::min_element(flow.begin(), flow.end());
    cost.rate = median(coreRate);
    cost.runs = flow.size();
    std::vector<double> fitError;
    for (size_t i = 0; i < flow.size(); ++i) fitError.push_back(std::abs(cost.flowToVerdict(residence[i]) - flow[i]) / flow[i]);
    cost.medianAbsError = median(fitError);
    return cost;
}

nlohmann::json forecastCampaign(const store::CampaignInfo& c, const std::vector<store::LedgerRun>& runs,
                                const ParameterSpace& space, const std::vector<WarmRun>& pool,
                                const std::map<int, double>& flowDone) {
    const auto feedOf = [&](const store::LedgerRun& r) { return mixerSceneFor(c.sceneJson, r.params).feedKgH; };
    // The model of log M takes design points once (a replicate repeats one).
    Design units;
    std::vector<double> logM;
    for (const auto* r : finishedOf(runs, pool)) {
        const auto m = runQuantity(*r, "mixer");
        if (!m || !(*m > 0) || store::isReplicate(*r)) continue;
        units.push_back(unitOf(space, *r));
        logM.push_back(std::log(*m));
    }
    const auto cost = fitRunCost(c, runs, pool);
    if (units.size() < 5 || !cost) return nullptr;

    nlohmann::json points = nlohmann::json::array();
    double left = 0, leftLow = 0, leftHigh = 0;
    for (const auto& r : runs) {
        if (r.status != "queued" && r.status != "running") continue;
        // Each point on its own: the model conditioned on the finished runs alone, as the warm
        // start that will begin it is chosen.
        const auto pick = mostUncertain(units, logM, {}, {unitOf(space, r)}, 1).picks.front();
        const double feed = feedOf(r);
        const auto it = flowDone.find(r.index);
        const double done = it == flowDone.end() ? 0.0 : it->second;
        // 90% of the model's predictive spread of log M; the cost follows M monotonically.
        const auto coreHours = [&](double logLoading) { return cost->coreHours(std::exp(logLoading), feed, done); };
        const double h = coreHours(pick.mean), lo = coreHours(pick.mean - 1.645 * pick.sd),
                     hi = coreHours(pick.mean + 1.645 * pick.sd);
        left += h, leftLow += lo, leftHigh += hi;
        points.push_back({{"index", r.index}, {"status", r.status}, {"replicate", store::isReplicate(r)},
                          {"predicted_loading_kg", std::exp(pick.mean)}, {"feed_kg_h", feed},
                          {"residence_s", std::exp(pick.mean) / feed * 3600.0},
                          {"flow_to_verdict_s", cost->flowToVerdict(std::exp(pick.mean) / feed * 3600.0)},
                          {"flow_done_s", done}, {"core_hours_left", h},
                          {"core_hours_left_90", {lo, hi}}});
    }
    return {{"points", points},
            {"core_hours_left", left},
            {"core_hours_left_90", {leftLow, leftHigh}},
            {"flow_fit", {{"intercept_s", cost->intercept}, {"per_residence_time", cost->perResidence}, {"floor_s", cost->floor},
                          {"runs", cost->runs}, {"median_abs_error", cost->medianAbsError}}},
            {"core_seconds_per_flow_second", cost->rate},
            {"model_runs", units.size()},
            {"method", "flow to verdict t = max(a + b M/feed, the fastest verdict) fitted on the steady runs; M from the kriging model of "
                       "their log loading (90% of its spread); core-seconds per second of flow: their median"}};
}

}  // namespace mixload::experiments
