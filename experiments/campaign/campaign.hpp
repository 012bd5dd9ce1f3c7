// SPDX-License-Identifier: GPL-3.0-or-later
// Offline full-CFD campaigns over a design of experiments, recorded in a SQLite ledger under
// <dir>/<name>/ledger.sqlite: create, extend, run (resumable, one driver at a time), status, export.
// Each call returns its summary as JSON; `mixload campaign` prints it.
#pragma once
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "doe/adaptive.hpp"
#include "scene/collapse_scene.hpp"
#include "scene/mixer_scene.hpp"
#include "store/ledger.hpp"

namespace mixload::experiments {

struct CampaignPlace {
    std::string name;
    std::string dir = "runs/campaigns";
    std::filesystem::path home() const { return std::filesystem::path(dir) / name; }
    std::filesystem::path ledger() const { return home() / "ledger.sqlite"; }
};

struct CampaignSpec {
    CampaignPlace place;
    std::string ranges;  // TOML file
    std::string design = "lhs", scene, method = "mrf", mesh;
    int n = 0;
    long long seed = 1;
    std::optional<double> cellSize, endTime, initialLoadingKg, steadyTol, steadyFlowTol, steadyResidence;
    std::string mesher = "ogrid";
    // Mixer: "label" (fullcfd/run/label_protocol: every point from one fixed deposit, windows of a
    // residence time, no warm start; the default) or "scene" (the scene's deposit and windows, or
    // those given). Giving initialLoadingKg or steadyResidence without a protocol means "scene".
    std::string protocol;
    // design "points": the points of this CSV (columns named as the ranges' parameters, or a
    // campaign export's), instead of a sampled design; every value inside the ranges.
    std::string points;
    std::string numerics = scene::MixerNumerics{}.preset;
};

struct CampaignRunOptions {
    int jobs = 1, np = 1;
    double maxHours = 0;
    bool snapshots = false, progress = true;
    // Mixer design points start from the latest fields of a finished run of the campaign instead of
    // the scene's deposit: the steady run whose loading is nearest a kriging prediction at the point
    // (five steady runs or more), else the nearest finished run in the unit cube. Replicates keep
    // their own deposits, and the first point, with nothing finished, starts from the deposit.
    bool warmNearest = false;
    // Also the finished runs of these campaigns (on the same base scene and mesh) as starts, with
    // warm-nearest implied: a hold-out campaign starts from its training campaign's runs.
    std::vector<CampaignPlace> warmFrom;
    // Called after each finished run, one at a time (e.g. checking a surrogate against the campaign).
    std::function<void()> afterRun;
};

// The run directory a mixer design point would start from under --warm-nearest (empty: the deposit).
std::filesystem::path campaignWarmSource(const CampaignPlace& place, int index, const std::vector<CampaignPlace>& from = {});

// Every point becomes a validated scene before the ledger exists: bad input leaves nothing.
nlohmann::json createCampaign(const CampaignSpec& spec);
// Adds n points without repeating any: the Sobol sequence continues where the campaign stopped; a
// Latin hypercube is augmented into the strata its points leave free. adaptive: the n points go
// where a kriging model of the finished runs' log quantity (mixer: loading_kg of steady runs;
// collapse: runout_star) is least sure, given the points already queued (doe/adaptive), by the
// model's variance alone or weighted by its leave-one-out errors nearby.
// inset: adaptive candidates keep this share of the unit width (of each parameter's range, or of
// its log-range) from every face of the design box, e.g. the margin by which the design's ranges
// were widened beyond the user's, so that the picks stay where answers are asked for.
// perCoreHour (mixer): the criterion per forecast core-hour of the point (campaign status's cost
// model on the campaign's steady runs); every mixer pick reports that forecast either way.
nlohmann::json extendCampaign(const CampaignPlace& place, int n, bool adaptive = false,
                              AdaptiveCriterion by = AdaptiveCriterion::Variance, double inset = 0, bool perCoreHour = false);
// Mixer campaigns: n finished, steady design points spread over the design (farthest-point), each
// queued again from a deposit of depositFactor times its loading. Their two results measure the
// label noise of the steady test (campaignNoise). Throws InputError with too few such points.
nlohmann::json replicateCampaign(const CampaignPlace& place, int n, double depositFactor);
// The finished replicate pairs, their relative differences, and one run's scatter estimated from
// them: sqrt(mean(rel^2) / 2) (null without a pair); what `surrogate fit --noise` takes. A pair
// whose loadings lie more than kTwoStatesRatio apart is two steady states of its point: flagged
// (two_states), counted (two_state_pairs) and left out of the scatter and of n.
inline constexpr double kTwoStatesRatio = 2.0;
nlohmann::json campaignNoise(const CampaignPlace& place);
// Counts, where each unfinished mixer point stands, and a forecast of the core-hours left
// (campaign/forecast), fitted on the campaign's finished runs and those of `with` (same base scene).
nlohmann::json campaignStatus(const CampaignPlace& place, const std::vector<CampaignPlace>& with = {});
nlohmann::json exportCampaignCsv(const CampaignPlace& place, const std::filesystem::path& csv);
// Runs queued points, jobs at a time, until none is left or maxHours; counts in the summary.
nlohmann::json runCampaign(const CampaignPlace& place, const CampaignRunOptions& options);

// What a finished run of the campaign measured: a mixer run's loading [kg] when its verdict is
// steady, a collapse run's runout L*f; nothing for a run that is not done or has no verdict.
std::optional<double> runQuantity(const store::LedgerRun& run, const std::string& scene);

// The campaign recorded in the place's ledger; throws InputError if there is none.
store::CampaignInfo openCampaign(const CampaignPlace& place, std::unique_ptr<store::Ledger>& ledger);
// The scene of one design point of a campaign (its base with the point's parameters), validated.
scene::MixerScene mixerSceneFor(const nlohmann::json& base, const nlohmann::json& params);
scene::CollapseScene collapseSceneFor(const nlohmann::json& base, const nlohmann::json& params);

}  // namespace mixload::experiments
