// SPDX-License-Identifier: GPL-3.0-or-later
#include "campaign/campaign.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <mutex>
#include <regex>
#include <set>
#include <sstream>
#include <thread>
#include <type_traits>

#include "campaign/design_space.hpp"
#include "cases/meshed_geometry.hpp"
#include "campaign/driver_lock.hpp"
#include "campaign/forecast.hpp"
#include "campaign/progress.hpp"
#include "campaign/retry.hpp"
#include "campaign/warm_start.hpp"
#include "common/atomic_file.hpp"
#include "common/clock.hpp"
#include "common/file_lock.hpp"
#include "common/input_error.hpp"
#include "common/process.hpp"
#include "common/progress.hpp"
#include "doe/adaptive.hpp"
#include "doe/designs.hpp"
#include "doe/parameter_space.hpp"
#include "mixload_version.hpp"
#include "post/mixer_results.hpp"
#include "run/collapse_job.hpp"
#include "run/foam_runner.hpp"
#include "run/label_protocol.hpp"
#include "run/mixer_job.hpp"
#include "store/campaign_fields.hpp"
#include "table.hpp"
#include "scene/collapse_overrides.hpp"
#include "scene/mixer_overrides.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {

void checkName(const std::string& name) {
    if (!std::regex_match(name, std::regex("[A-Za-z0-9_.-]{1,64}")))
        throw InputError("name", name, "1-64 letters, digits, '_', '-' or '.'");
}

// The base inputs of a campaign, as stored in the ledger; every point applies its params on top.
nlohmann::json baseOf(const CampaignSpec& o, const std::string& kind) {
    if (kind == "mixer") {
        nlohmann::json b{{"kind", kind}, {"scene", o.scene.empty() ? scene::kDefaultMixerScene : o.scene},
                         {"method", o.method}, {"mesh", o.mesh.empty() ? "coarse" : o.mesh}};
        if (o.cellSize) b["cell_size_m"] = *o.cellSize, b["mesh"] = "custom";
        if (o.endTime) b["end_time_s"] = *o.endTime;
        if (o.steadyTol) b["steady_tol"] = *o.steadyTol;
        if (o.steadyFlowTol) b["steady_flow_tol"] = *o.steadyFlowTol;
        b["mesher"] = o.mesher;
        b["numerics"] = o.numerics;
        const std::string protocol =
            !o.protocol.empty() ? o.protocol : (o.initialLoadingKg || o.steadyResidence) ? "scene" : "label";
        if (protocol == "label") {
            // The protocol's own start, windows and cap (the same keys a scene-protocol base has, so
            // a point's scene is built the one way); applyLabelProtocol refuses a start of its own.
            scene::MixerOverrides m;
            m.initialLoadingKg = o.initialLoadingKg;
            m.residence = o.steadyResidence;
            m.endTime = o.endTime;
            run::applyLabelProtocol(m);
            b["protocol"] = run::kLabelProtocol;
            b["initial_loading_kg"] = *m.initialLoadingKg;
            b["steady_window_residence"] = *m.residence;
            b["end_time_s"] = *m.endTime;
        } else if (protocol == "scene") {
            if (o.initialLoadingKg) b["initial_loading_kg"] = *o.initialLoadingKg;
            b["steady_window_residence"] = o.steadyResidence.value_or(scene::MixerScene{}.steadyResidence);
        } else {
            throw InputError("protocol", protocol, "label | scene");
        }
        return b;
    }
    if (o.cellSize || o.endTime || o.initialLoadingKg || o.steadyTol || o.steadyFlowTol || o.steadyResidence ||
        !o.protocol.empty())
        throw InputError("cell-size, end-time, initial-loading-kg, steady-tol, steady-flow-tol, steady-window-residence, protocol", "(given)",
                         "mixer campaigns only");
    return {{"kind", kind}, {"material", o.scene.empty() ? "quartz" : o.scene},
            {"cells_per_length", o.mesh.empty() ? 30 : std::stoi(o.mesh)}};
}

double param(const nlohmann::json& p, const char* k) { return p.at(k).get<double>(); }

}  // namespace

// The scene of one design point (validated); mu_d = mu_s + delta_mu.
scene::MixerScene mixerSceneFor(const nlohmann::json& base, const nlohmann::json& p) {
    scene::MixerOverrides m;
    m.scene = base["scene"];
    m.method = base["method"].get<std::string>();
    if (base.contains("cell_size_m")) m.cellSize = base["cell_size_m"].get<double>();
    else m.mesh = base["mesh"].get<std::string>();
    if (base.contains("end_time_s")) m.endTime = base["end_time_s"].get<double>();
    if (base.contains("initial_loading_kg"))
        m.initialLoadingKg = base["initial_loading_kg"].get<double>();
    if (base.contains("steady_tol")) m.tol = base["steady_tol"].get<double>();
    if (base.contains("steady_flow_tol")) m.flowTol = base["steady_flow_tol"].get<double>();
    // Campaigns created before these settings existed ran on the snappy mesh with windows of
    // revolutions only: without the keys, their points keep those scenes (and hashes).
    m.mesher = base.value("mesher", std::string("snappy"));
    m.residence = base.value("steady_window_residence", 0.0);
    // Likewise the numerics presets: older bases ran the legacy settings.
    m.numerics = base.value("numerics", std::string("legacy"));
    const double muS0 = m.build().material.muS;
    if (p.contains("mu_s")) m.muS = param(p, "mu_s");
    if (p.contains("delta_mu")) m.muD = m.muS.value_or(muS0) + param(p, "delta_mu");
    if (p.contains("i0")) m.I0 = param(p, "i0");
    if (p.contains("d")) m.d = param(p, "d");
    if (p.contains("rho")) m.rho = param(p, "rho");
    if (p.contains("feed_kg_h")) m.feedKgH = param(p, "feed_kg_h");
    if (p.contains("rpm")) m.rpm = param(p, "rpm");
    // A replicate of a design point starts from its own deposit (campaign replicate).
    if (p.contains("initial_loading_kg")) m.initialLoadingKg = param(p, "initial_loading_kg");
    return m.build();
}

scene::CollapseScene collapseSceneFor(const nlohmann::json& base, const nlohmann::json& p) {
    scene::CollapseOverrides c;
    c.material = base["material"];
    c.cellsPerLength = base["cells_per_length"];
    const double muS0 = c.scene().material.muS;
    if (p.contains("mu_s")) c.muS = param(p, "mu_s");
    if (p.contains("delta_mu")) c.muD = c.muS.value_or(muS0) + param(p, "delta_mu");
    if (p.contains("i0")) c.I0 = param(p, "i0");
    if (p.contains("aspect")) c.aspect = param(p, "aspect");
    return c.scene();
}

namespace {

std::string sceneHashFor(const nlohmann::json& base, const nlohmann::json& p) {
    return base["kind"] == "mixer" ? mixerSceneFor(base, p).hash() : collapseSceneFor(base, p).hash();
}

std::vector<nlohmann::json> pointsOf(const ParameterSpace& space, const nlohmann::json& base,
                                     const Design& unit) {
    std::vector<nlohmann::json> points;
    for (const auto& u : unit) {
        const auto x = space.toPhysical(u);
        nlohmann::json p;
        for (size_t j = 0; j < x.size(); ++j) p[space.params[j].name] = x[j];
        p["scene_hash"] = sceneHashFor(base, p);
        points.push_back(p);
    }
    return points;
}

std::string csvField(const nlohmann::json& v) {
    if (v.is_null()) return "";
    if (v.is_string()) {
        std::string s = v.get<std::string>();
        if (s.find_first_of(",\"\n") == std::string::npos) return s;
        std::string q = "\"";
        for (char ch : s) q += ch == '"' ? std::string("\"\"") : std::string(1, ch);
        return q + "\"";
    }
    return v.dump();
}

// One design point in its own directory <home>/runs/<index>-<scene hash>; a second attempt runs the
// retry's scene, which has a hash (and so a directory) of its own.
template <class Scene>
fs::path pointDir(const fs::path& home, int index, const Scene& s) {
    return home / "runs" / (std::to_string(index) + "-" + s.hash());
}

template <class Job, class Scene, class Run>
nlohmann::json runPoint(const Scene& s, int np, bool snapshots, const fs::path& home, int index,
                        std::optional<std::chrono::steady_clock::time_point> deadline, Run run,
                        const fs::path& warmFrom = {}) {
    Job job;
    if constexpr (std::is_same_v<Job, run::MixerJob>) job.warmFrom = warmFrom;
    job.scene = s;
    job.np = np;
    job.snapshots = snapshots;
    job.out = pointDir(home, index, s);
    job.deadline = deadline;
    return run(job);
}

}  // namespace

namespace {

// A points design: each row of the CSV as a point, its parameters those of the ranges; an input
// the ranges leave out must hold the base scene's value (a relabel must not change it unseen).
std::vector<nlohmann::json> pointsFromCsv(const ParameterSpace& space, const nlohmann::json& base, const fs::path& csv) {
    if (space.scene != "mixer") throw InputError("points", csv.string(), "a mixer campaign's ranges (scene = \"mixer\")");
    const auto rows = surrogates::readInputs(csv);
    if (rows.empty()) throw InputError("points", csv.string(), "a CSV with at least one row");
    const auto s0 = mixerSceneFor(base, nlohmann::json::object());
    const auto valueOf = [](const surrogates::Point& x, const std::string& name) {
        using namespace surrogates;
        return name == "mu_s" ? x[kMuS] : name == "delta_mu" ? x[kMuD] - x[kMuS] : name == "i0" ? x[kI0]
             : name == "d" ? x[kD] : name == "rho" ? x[kRho] : name == "feed_kg_h" ? x[kFeed] : x[kRpm];
    };
    const std::map<std::string, double> fixed{{"mu_s", s0.material.muS}, {"delta_mu", s0.material.muD - s0.material.muS},
                                              {"i0", s0.material.I0}, {"d", s0.material.grainDiameter},
                                              {"rho", s0.bulkDensity()}, {"feed_kg_h", s0.feedKgH}, {"rpm", s0.rpm}};
    std::vector<nlohmann::json> points;
    for (size_t i = 0; i < rows.size(); ++i) {
        nlohmann::json p;
        std::set<std::string> ranged;
        for (const auto& prm : space.params) {
            const double v = valueOf(rows[i], prm.name);
            if (!(v >= prm.min && v <= prm.max))
                throw InputError("points", csv.string() + " row " + std::to_string(i + 1) + " " + prm.name + " = " + formatNumber(v),
                                 "[" + formatNumber(prm.min) + ", " + formatNumber(prm.max) + "] (the ranges file)");
            p[prm.name] = v;
            ranged.insert(prm.name);
        }
        for (const auto& [name, v0] : fixed) {
            const double v = valueOf(rows[i], name);
            if (!ranged.count(name) && std::abs(v - v0) > 1e-9 * std::max(1.0, std::abs(v0)))
                throw InputError("points", csv.string() + " row " + std::to_string(i + 1) + " " + name + " = " + formatNumber(v),
                                 formatNumber(v0) + ", the base scene's value (the ranges file does not vary " + name + ")");
        }
        p["scene_hash"] = sceneHashFor(base, p);
        points.push_back(p);
    }
    return points;
}

}  // namespace

nlohmann::json createCampaign(const CampaignSpec& o) {
    checkName(o.place.name);
    const bool fromPoints = !o.points.empty();
    if (fromPoints && o.design != "lhs" && o.design != "points")
        throw InputError("design", o.design, "points (or left out) with --points");
    if (!fromPoints) requireRange("n", o.n, 1, 100000);
    if (!fromPoints && o.design != "lhs" && o.design != "sobol") throw InputError("design", o.design, "lhs|sobol (points needs --points FILE.csv)");
    if (fs::exists(o.place.ledger()))
        throw InputError("name", o.place.name, "a new campaign (" + o.place.ledger().string() + " exists)");
    const auto space = loadRanges(o.ranges);
    if (!o.mesh.empty() && space.scene == "collapse" && !std::regex_match(o.mesh, std::regex("[0-9]{1,3}")))
        throw InputError("mesh", o.mesh, "cells per column length (e.g. 30) for a collapse campaign");
    const nlohmann::json base = baseOf(o, space.scene);
    // Every point becomes a validated scene before the ledger exists: bad input leaves nothing.
    const auto points = fromPoints ? pointsFromCsv(space, base, o.points)
                                   : pointsOf(space, base,
                                              o.design == "lhs" ? latinHypercube(o.n, static_cast<int>(space.params.size()),
                                                                                 static_cast<std::uint64_t>(o.seed))
                                                                : sobol(o.n, static_cast<int>(space.params.size())));
    // The points vary the powder and the operating point, never the impeller: one check of the base
    // scene's geometry on its mesh covers them all.
    if (space.scene == "mixer") cases::requireSceneGeometry(mixerSceneFor(base, nlohmann::json::object()));
    store::CampaignInfo info;
    info.name = o.place.name;
    info.scene = space.scene;
    info.sceneJson = base;
    info.sceneHash = sceneHashFor(base, nlohmann::json::object());
    info.rangesToml = readFile(o.ranges);
    info.design = fromPoints ? "points" : o.design;
    info.seed = static_cast<std::uint64_t>(o.seed);
    info.method = space.scene == "mixer" ? o.method : "";
    info.mesh = base.contains("mesh") ? base["mesh"].get<std::string>()
                                      : std::to_string(base["cells_per_length"].get<int>());
    info.mixloadVersion = kVersion;
    info.gitCommit = kGitCommit;
    store::Ledger ledger(o.place.ledger());
    ledger.createCampaign(info, points);
    return {{"campaign", o.place.name}, {"ledger", o.place.ledger().string()},
            {"scene", space.scene}, {"design", info.design}, {"points", points.size()},
            {"protocol", base.value("protocol", space.scene == "mixer" ? "scene" : "")},
            {"parameters", [&] {
                 nlohmann::json a = nlohmann::json::array();
                 for (const auto& p : space.params)
                     a.push_back({{"name", p.name}, {"unit", p.unit}, {"min", p.min}, {"max", p.max}});
                 return a;
             }()}};
}

namespace {

// Held while a design is read and points are added to it: two `extend` or `replicate` commands at
// once would each read the same design and add the same points.
std::unique_ptr<FileLock> designLock(const CampaignPlace& o) {
    return std::make_unique<FileLock>(o.home() / "design.lock", FileLock::Mode::wait);
}

}  // namespace

store::CampaignInfo openCampaign(const CampaignPlace& o, std::unique_ptr<store::Ledger>& l) {
    checkName(o.name);
    if (!fs::exists(o.ledger()))
        throw InputError("name", o.name, "an existing campaign (no " + o.ledger().string() + ")");
    l = std::make_unique<store::Ledger>(o.ledger());
    auto c = l->campaign(o.name);
    if (!c) throw InputError("name", o.name, "a campaign recorded in " + o.ledger().string());
    return *c;
}

std::optional<double> runQuantity(const store::LedgerRun& r, const std::string& scene) {
    if (r.status != "done" || !r.result.is_object()) return std::nullopt;
    const bool mixer = scene == "mixer";
    if (mixer && !r.result.value("steady", false)) return std::nullopt;
    const auto q = r.result.value(mixer ? "loading_kg" : "runout_star", nlohmann::json());
    return q.is_number() ? std::optional<double>(q.get<double>()) : std::nullopt;
}

namespace {

// How many points of the Sobol sequence a design holds: its own points are the sequence's first
// ones, and replicates (a point again) and adaptive picks (off the sequence) are not among them.
int sobolPointsOf(const Design& units, int k) {
    const auto seq = sobol(static_cast<int>(units.size()), k, 0);
    int n = 0;
    for (const auto& p : seq) {
        const bool held = std::any_of(units.begin(), units.end(), [&](const auto& u) { return distance2(u, p) < 1e-12; });
        if (!held) break;
        ++n;
    }
    return n;
}

}  // namespace

// Adds n points without repeating any: the Sobol sequence continues where the campaign stopped;
// a Latin hypercube is augmented into the strata its points leave free; adaptive points go where
// a kriging model of the finished runs is least sure.
nlohmann::json extendCampaign(const CampaignPlace& o, int n, bool adaptive, AdaptiveCriterion by, double inset, bool perCoreHour) {
    requireRange("n", n, 1, 100000);
    requireRange("inset", inset, 0.0, 0.25);
    std::unique_ptr<store::Ledger> l;
    const auto c = openCampaign(o, l);
    const auto lock = designLock(o);
    const auto space = rangesOf(c, o.name);
    const auto runs = l->runs(o.name);
    Design old;
    for (const auto& r : runs) old.push_back(unitOf(space, r));
    const int k = static_cast<int>(space.params.size());
    nlohmann::json out{{"campaign", o.name}};
    Design unit;
    if (adaptive) {
        // The model learns the log of the campaign's quantity (the loading spans decades) from its
        // finished runs (a mixer run counts only with a steady verdict); queued and running points
        // are conditioned on, failed ones left out.
        const char* quantity = space.scene == "mixer" ? "loading_kg" : "runout_star";
        Design done, pending;
        std::vector<double> y;
        for (size_t i = 0; i < runs.size(); ++i) {
            const auto& r = runs[i];
            if (r.status == "queued" || r.status == "running") pending.push_back(old[i]);
            const auto q = runQuantity(r, space.scene);
            if (!q || !(*q > 0)) continue;
            done.push_back(old[i]);
            y.push_back(std::log(*q));
        }
        // Candidates: a Sobol set of 256 points per dimension (at least 1024), far along the
        // sequence so that it does not coincide with a Sobol design's own points.
        const int nc = std::max(1024, 256 * k);
        // A variance criterion is largest on the box's faces; inset keeps the picks off them.
        Design candidates = sobol(nc, k, 100000);
        for (auto& u : candidates)
            for (auto& x : u) x = inset + (1 - 2 * inset) * x;
        const auto paramsAt = [&](const std::vector<double>& u) {
            const auto x = space.toPhysical(u);
            nlohmann::json params = nlohmann::json::object();
            for (size_t i = 0; i < x.size(); ++i) params[space.params[i].name] = x[i];
            return params;
        };
        // What a mixer point would cost, from the campaign's own runs (campaign status's forecast):
        // each pick says it, and with perCoreHour the picks are chosen by it.
        const auto cost = space.scene == "mixer" ? fitRunCost(c, runs, {}) : std::nullopt;
        if (perCoreHour && !cost)
            throw InputError("per-core-hour", o.name,
                             "a mixer campaign with at least five steady runs that recorded their flow and core-seconds");
        const auto coreHoursAt = [&](const std::vector<double>& u, double logM) {
            return cost->coreHours(std::exp(logM), mixerSceneFor(c.sceneJson, paramsAt(u)).feedKgH);
        };
        const auto batch = mostUncertain(done, y, pending, candidates, n, by, perCoreHour ? PointCost(coreHoursAt) : PointCost());
        nlohmann::json picks = nlohmann::json::array();
        for (const auto& p : batch.picks) {
            unit.push_back(p.unit);
            picks.push_back({{"params", paramsAt(p.unit)}, {"predicted", std::exp(p.mean)}, {"sd_log", p.sd}, {"loo_weight", p.weight},
                             {"core_hours", cost ? nlohmann::json(coreHoursAt(p.unit, p.mean)) : nlohmann::json()}});
        }
        out["adaptive"] = {{"quantity", quantity},
                           {"model", "kriging of log " + std::string(quantity) + " on " + std::to_string(done.size()) + " finished runs"},
                           {"criterion", by == AdaptiveCriterion::Variance ? "variance" : "loo-weighted"},
                           {"inset", inset},
                           {"per_core_hour", perCoreHour},
                           {"finished_runs", done.size()},
                           {"pending_runs", pending.size()},
                           {"loo_mean_abs_error_log", batch.looMeanAbsError},
                           {"max_sd_log_before", batch.maxSdBefore},
                           {"picks", picks}};
    } else {
        if (c.design == "points")
            throw InputError("campaign", o.name, "a sampled design to extend (a points design has no sequence to continue; use --adaptive or a new campaign)");
        // A Sobol design continues its own sequence: replicates and adaptive picks are not of it.
        unit = c.design == "sobol" ? sobol(n, k, sobolPointsOf(old, k))
                                   : augmentLatinHypercube(old, n, c.seed + runs.size());
    }
    const auto points = pointsOf(space, c.sceneJson, unit);
    l->addPoints(o.name, points);
    out["added"] = points.size();
    out["points"] = runs.size() + points.size();
    return out;
}

nlohmann::json replicateCampaign(const CampaignPlace& o, int n, double depositFactor) {
    requireRange("n", n, 1, 1000);
    requireRange("deposit-factor", depositFactor, 0.05, 5.0);
    std::unique_ptr<store::Ledger> l;
    const auto c = openCampaign(o, l);
    if (c.scene != "mixer") throw InputError("campaign", o.name, "a mixer campaign (a replicate starts from another deposit)");
    const auto lock = designLock(o);
    const auto space = rangesOf(c, o.name);
    const auto runs = l->runs(o.name);
    // Candidates: finished, steady design points that are not replicates themselves.
    std::vector<const store::LedgerRun*> done;
    std::vector<double> loading;
    Design units;
    std::set<std::string> hashes;
    for (const auto& r : runs) {
        hashes.insert(r.params.value("scene_hash", std::string()));
        const auto m = runQuantity(r, c.scene);
        if (!m || store::isReplicate(r)) continue;
        done.push_back(&r);
        loading.push_back(*m);
        units.push_back(unitOf(space, r));
    }
    if (static_cast<int>(done.size()) < n)
        throw InputError("n", std::to_string(n), "at most the " + std::to_string(done.size()) + " finished, steady design points");
    // Spread over the design: the first finished point, then each time the one farthest from
    // those already taken (in the unit cube). Every point is ordered so, and the first n whose
    // replicate is a new run are taken: a deposit equal to the point's own start (a label point of
    // 0.1 kg replicated from 0.05 kg, its protocol's deposit) would only repeat the run.
    std::vector<size_t> chosen{0};
    while (chosen.size() < done.size()) {
        double best = -1;
        size_t at = 0;
        for (size_t i = 0; i < done.size(); ++i) {
            double nearest = 1e300;
            for (size_t j : chosen) nearest = std::min(nearest, distance2(units[i], units[j]));
            if (nearest > best) best = nearest, at = i;
        }
        chosen.push_back(at);
    }
    std::vector<nlohmann::json> points;
    nlohmann::json added = nlohmann::json::array();
    int taken = 0;  // replicates queued now or before, of the points walked
    for (size_t i : chosen) {
        if (taken == n) break;
        auto p = done[i]->params;
        const double m = loading[i];
        p["initial_loading_kg"] = std::round(1000 * depositFactor * m) / 1000;  // grams: a deposit, not a measurement
        p.erase("scene_hash");
        p["scene_hash"] = sceneHashFor(c.sceneJson, p);
        if (p["scene_hash"] == done[i]->params.value("scene_hash", std::string())) continue;  // the point's own run
        ++taken;
        if (!hashes.insert(p["scene_hash"].get<std::string>()).second) continue;  // this replicate exists
        added.push_back({{"of_index", done[i]->index}, {"loading_kg", m}, {"initial_loading_kg", p["initial_loading_kg"]}});
        points.push_back(p);
    }
    if (!points.empty()) l->addPoints(o.name, points);
    return {{"campaign", o.name}, {"added", points.size()}, {"replicates", added}, {"points", runs.size() + points.size()}};
}

nlohmann::json campaignNoise(const CampaignPlace& o) {
    std::unique_ptr<store::Ledger> l;
    const auto c = openCampaign(o, l);
    const auto runs = l->runs(o.name);
    // A replicate matches its design point on every parameter but the deposit.
    const auto key = [](nlohmann::json p) {
        p.erase("initial_loading_kg");
        p.erase("scene_hash");
        return p.dump();
    };
    std::map<std::string, const store::LedgerRun*> originals;
    for (const auto& r : runs)
        if (!store::isReplicate(r)) originals[key(r.params)] = &r;
    nlohmann::json pairs = nlohmann::json::array();
    double sum2 = 0;
    int n = 0, nTwoStates = 0;
    for (const auto& r : runs) {
        if (!store::isReplicate(r)) continue;
        const auto it = originals.find(key(r.params));
        if (it == originals.end()) continue;
        const auto ma = runQuantity(*it->second, c.scene), mb = runQuantity(r, c.scene);
        if (!ma || !mb) continue;
        const double a = *ma, b = *mb;
        // Relative difference of the two results about their mean: each run's own scatter is
        // this over sqrt(2).
        const double rel = (b - a) / (0.5 * (a + b));
        // Two loadings a factor of 2 apart are two steady states of one point (a bed and a film:
        // 5-15x apart), not the steady test's scatter (its pairs differ by at most a few percent):
        // listed, and left out of the noise a model's nugget takes.
        const bool twoStates = std::max(a, b) > kTwoStatesRatio * std::min(a, b);
        // The deposit a coarse mesh actually laid can differ from the one asked: start.laid_kg, or
        // for runs recorded before it, the first loading in the run directory's result.
        nlohmann::json start = r.result.is_object() ? r.result.value("start", nlohmann::json::object()) : nlohmann::json::object();
        std::error_code ec;
        if (!start.contains("laid_kg") && !r.runDir.empty() && fs::exists(fs::path(r.runDir) / "result.json", ec)) {
            const auto full = nlohmann::json::parse(readFile(fs::path(r.runDir) / "result.json"), nullptr, false);
            if (full.is_object() && full.contains("initial_loading_kg")) start["laid_kg"] = full["initial_loading_kg"];
        }
        pairs.push_back({{"index", it->second->index}, {"replicate_index", r.index}, {"loading_kg", a}, {"replicate_kg", b},
                         {"initial_loading_kg", r.params["initial_loading_kg"]},
                         {"laid_kg", start.contains("laid_kg") ? start["laid_kg"] : nlohmann::json()},
                         {"laid_far_from_asked", start.contains("laid_kg") && run::laidFarFromAsked(r.params["initial_loading_kg"].get<double>(),
                                                                                                   start["laid_kg"].get<double>())},
                         {"relative_difference", rel}, {"two_states", twoStates}});
        if (twoStates) {
            ++nTwoStates;
            continue;
        }
        sum2 += rel * rel;
        ++n;
    }
    nlohmann::json out{{"campaign", o.name}, {"pairs", pairs}, {"n", n}, {"two_state_pairs", nTwoStates}};
    out["run_noise"] = n ? nlohmann::json(std::sqrt(sum2 / n / 2)) : nlohmann::json();
    return out;
}

nlohmann::json campaignStatus(const CampaignPlace& o, const std::vector<CampaignPlace>& with) {
    std::unique_ptr<store::Ledger> l;
    const auto c = openCampaign(o, l);
    const auto runs = l->runs(o.name);
    double wall = 0, core = 0;
    for (const auto& r : runs) wall += r.wallSeconds.value_or(0), core += r.coreSeconds.value_or(0);
    nlohmann::json out{{"campaign", o.name}, {"scene", c.scene}, {"design", c.design},
                       {"points", runs.size()}, {"counts", l->status(o.name)},
                       {"wall_seconds_done", wall}, {"core_seconds_done", core},
                       {"integrity_ok", l->integrityOk()}, {"created", c.created},
                       {"mixload_version", c.mixloadVersion}, {"git_commit", c.gitCommit}};
    // Whether a driver holds the campaign now: a row left "running" by a driver that died is only
    // requeued by the next `campaign run`, and until then looks like a live one.
    try {
        const FileLock probe(o.home() / "driver.lock", FileLock::Mode::tryOnce);
        out["driver_running"] = !probe.held();
    } catch (const std::exception&) {
        out["driver_running"] = nullptr;  // the lock cannot be opened (a read-only copy): unknown
    }
    // Where each unfinished mixer point stands in its run directory: a low-feed bed runs for hours,
    // and its loading and outflow against the feed say how far it is from steady.
    nlohmann::json unfinished = nlohmann::json::array();
    // Flow run on each point: its directory's, with the kept progress it continues; a point whose
    // directory is gone has its kept progress alone.
    std::map<int, double> flowDone = c.scene == "mixer" ? keptProgressFlow(o.home()) : std::map<int, double>{};
    if (c.scene == "mixer" && fs::is_directory(o.home() / "runs"))
        for (const auto& r : runs) {
            if (r.status == "done" || r.status == "failed") continue;
            for (const auto& e : fs::directory_iterator(o.home() / "runs")) {
                const std::string name = e.path().filename().string();
                if (!e.is_directory() || name.rfind(std::to_string(r.index) + "-", 0) != 0 ||
                    name.find('.') != std::string::npos || fs::exists(e.path() / "result.json"))
                    continue;
                try {
                    const auto history = post::readLoadingHistory(e.path());
                    if (history.empty()) continue;
                    // Over the last 10 s of flow (the per-step outflow swings with the paddles).
                    const auto& last = history.back();
                    auto before = history.begin();
                    while (std::next(before) != history.end() && std::next(before)->t <= last.t - 10.0) ++before;
                    const double span = last.t - before->t;
                    const double flowBefore = flowBeforeRun(e.path());
                    // A retry runs in a directory of its own: the first attempt's, named by the
                    // point's scene hash, is then left behind and no longer runs.
                    const bool firstAttemptDir = name == std::to_string(r.index) + "-" + r.params.value("scene_hash", "");
                    const std::string attempt = firstAttemptDir ? (r.attempts > 1 ? "first, left" : "first") : "retry";
                    if (attempt != "first, left") flowDone[r.index] = flowBefore + last.t;  // what the forecast counts
                    unfinished.push_back({{"index", r.index}, {"status", r.status}, {"attempt", attempt}, {"run_dir", e.path().string()},
                                          {"time_s", last.t}, {"flow_before_s", flowBefore}, {"loading_kg", last.loading},
                                          {"loading_10s_before_kg", before->loading},
                                          {"outflow_kg_h", span > 0 ? (last.out - before->out) / span * 3600.0 : last.outflow * 3600.0},
                                          {"feed_kg_h", r.params.value("feed_kg_h", nlohmann::json())}});
                } catch (const std::exception&) {
                    // A history being written can be cut mid-line: the next look reads it whole.
                }
            }
        }
    out["unfinished"] = unfinished;
    if (c.scene == "mixer") {
        const auto pool = warmPool(c, with);
        out["forecast"] = forecastCampaign(c, runs, rangesOf(c, o.name), pool, flowDone);
        out["forecast_with"] = nlohmann::json::array();
        for (const auto& p : with) out["forecast_with"].push_back(p.name);
    }
    return out;
}

nlohmann::json exportCampaignCsv(const CampaignPlace& o, const std::filesystem::path& csv) {
    if (csv.empty()) throw InputError("output", "(missing)", "-o FILE.csv");
    std::unique_ptr<store::Ledger> l;
    const auto c = openCampaign(o, l);
    const auto runs = l->runs(o.name);
    std::set<std::string> params, qois;
    for (const auto& r : runs) {
        for (const auto& [k, _] : r.params.items()) params.insert(k);
        if (r.result.is_object())
            for (const auto& [k, v] : r.result.items())
                if (v.is_number() || v.is_boolean() || v.is_null() || v.is_string()) qois.insert(k);
    }
    // A mixer design may hold inputs at the base scene's values (a similarity design fixes rho and
    // I0): they get columns too, so the CSV carries every input a surrogate needs.
    std::vector<std::string> fixed;
    if (c.scene == "mixer")
        for (const char* k : {"mu_s", "delta_mu", "i0", "d", "rho", "feed_kg_h", "rpm"})
            if (!params.count(k)) fixed.push_back(k);
    const auto fixedValue = [&](const store::LedgerRun& r, const std::string& k) {
        const auto sc = mixerSceneFor(c.sceneJson, r.params);
        const auto& m = sc.material;
        return k == "mu_s" ? m.muS : k == "delta_mu" ? m.muD - m.muS : k == "i0" ? m.I0 : k == "d" ? m.grainDiameter
             : k == "rho" ? m.bulkDensity() : k == "feed_kg_h" ? sc.feedKgH : sc.rpm;
    };
    std::ostringstream os;
    os << "# campaign " << o.name << ", scene " << c.scene << ", design " << c.design << ", seed "
       << c.seed << ", base " << c.sceneJson.dump() << ", created " << c.created << " by mixload "
       << c.mixloadVersion << " (" << c.gitCommit << ")\n";
    os << "index";
    for (const auto& p : params) os << ',' << p;
    for (const auto& p : fixed) os << ',' << p;
    os << ",status,attempts,wall_seconds,core_seconds";
    for (const auto& q : qois) os << ',' << q;
    const bool mixer = c.scene == "mixer";
    // Where a finished mixer run started: the deposit, or the run whose fields it began from.
    // A run that continues a lost one's kept progress: "continued:" and where that one began.
    const std::function<std::string(const nlohmann::json&)> startOf = [&](const nlohmann::json& result) -> std::string {
        if (!result.is_object() || !result.contains("start")) return "";
        const auto& st = result["start"];
        if (st.contains("first_start")) return "continued:" + startOf({{"start", st["first_start"]}});
        if (st.contains("warm_from")) return "warm:" + fs::path(st["warm_from"].get<std::string>()).filename().string();
        return st.contains("deposit_kg") ? "deposit:" + formatNumber(st["deposit_kg"].get<double>()) : "";
    };
    if (mixer) os << ",start";
    os << ",run_dir,error\n";
    for (const auto& r : runs) {
        os << r.index;
        for (const auto& p : params) os << ',' << csvField(r.params.value(p, nlohmann::json()));
        for (const auto& p : fixed) os << ',' << csvField(fixedValue(r, p));
        os << ',' << r.status << ',' << r.attempts << ','
           << (r.wallSeconds ? std::to_string(*r.wallSeconds) : "") << ','
           << (r.coreSeconds ? std::to_string(*r.coreSeconds) : "");
        for (const auto& q : qois)
            os << ',' << csvField(r.result.is_object() ? r.result.value(q, nlohmann::json()) : nlohmann::json());
        if (mixer) os << ',' << startOf(r.result);
        os << ',' << csvField(r.runDir) << ',' << csvField(r.error) << '\n';
    }
    writeFileAtomic(csv, os.str());
    return {{"csv", csv.string()}, {"rows", runs.size()}};
}

// One driver per campaign: an advisory lock that the kernel drops when the driver dies, however.
nlohmann::json runCampaign(const CampaignPlace& place, const CampaignRunOptions& o) {
    requireRange("jobs", o.jobs, 1, 64);
    requireRange("np", o.np, 1, 256);
    requireRange("max-hours", o.maxHours, 0, 1e5);
    std::unique_ptr<store::Ledger> ledger;
    const auto c = openCampaign(place, ledger);
    const fs::path home = place.home();
    const DriverLock lock(home, "campaign run");
    if ((o.warmNearest || !o.warmFrom.empty()) && c.scene != "mixer")
        throw InputError("warm-nearest", "on", "a mixer campaign (a collapse starts from its column)");
    // In the bed-to-film band the start picks the steady state, so a warm start may make a label only
    // where paired cold and warm runs agree within the label noise; no regime has that measurement yet.
    if ((o.warmNearest || !o.warmFrom.empty()) && c.sceneJson.value("protocol", "") == run::kLabelProtocol)
        throw InputError(o.warmNearest ? "warm-nearest" : "warm-from-campaign", "on",
                         std::string("a campaign without the label protocol: ") + place.name + " makes labels (" +
                             run::kLabelProtocol + "), and a warm start makes none until paired cold and warm runs "
                             "agree within the label noise in its regime (docs/campaigns.md, \"Label protocol\")");
    const auto space = rangesOf(c, place.name);
    const auto warmRuns = warmPool(c, o.warmFrom);
    // Whatever a previous driver left running died with it (its solvers die with their parent).
    const int recovered = ledger->requeueRunning(place.name);
    const auto start = std::chrono::steady_clock::now();
    const auto deadline = deadlineAfterHours(o.maxHours);
    const auto total = ledger->runs(place.name).size();
    const nlohmann::json before = ledger->status(place.name);
    std::atomic<size_t> finished{before["done"].get<size_t>() + before["failed"].get<size_t>()};
    std::atomic<bool> stopped{false};
    std::atomic<int> unrecorded{0};
    std::mutex m;
    Progress bar("campaign " + place.name, o.progress);
    bar.update(double(finished) / total, std::to_string(finished.load()) + "/" + std::to_string(total));
    // Where a mixer point starts: its own kept progress when its directory was lost; else, under
    // --warm-nearest, a finished run (a replicate's deposit is the point of its run: it never starts
    // warm); else the deposit. Field-file starts copy cells at the rotor's angle 0, so a sliding-mesh
    // point takes none (its source had turned). Choosing a start never fails a point: it warns and
    // falls back to the deposit.
    const auto startOf = [&](store::Ledger& l, const store::LedgerRun& r, const scene::MixerScene& s,
                             const fs::path& dir) -> fs::path {
        const bool fieldStarts = s.method != "sm";
        try {
            if (fieldStarts)
                if (auto p = progressStart(home, r.index, dir); !p.empty()) return p;
            if (!(o.warmNearest || !o.warmFrom.empty()) || store::isReplicate(r)) return {};
            auto w = warmSourceFor(l.runs(place.name), home, space, r, warmRuns);
            return fieldStarts || w.extension() != ".h5" ? w : fs::path();
        } catch (const std::exception& e) {
            std::cerr << "mixload: warning: no start found for point " << r.index << " (" << e.what()
                      << "); it starts from its deposit\n";
            return {};
        }
    };
    const auto worker = [&] {
        store::Ledger l(home / "ledger.sqlite");
        for (;;) {
            if (timeIsUp(deadline)) {
                stopped = true;
                return;
            }
            const auto r = l.claimNext(place.name, 2, false);
            if (!r) return;
            const bool retry = r->attempts > 1;
            bool done = false;
            nlohmann::json res;
            fs::path dir;  // a mixer point's run directory
            try {
                if (c.scene == "mixer") {
                    auto s = mixerSceneFor(c.sceneJson, r->params);
                    if (retry) s = retryScene(s);
                    dir = pointDir(home, r->index, s);
                    const fs::path warm = startOf(l, *r, s, dir);
                    const auto runFrom = [&](const fs::path& w) {
                        return runPoint<run::MixerJob>(s, o.np, o.snapshots, home, r->index, deadline, run::runMixer, w);
                    };
                    if (warm.extension() != ".h5") {
                        res = runFrom(warm);
                    } else {
                        // A field file laid on a case that does not take it (another mesh, an
                        // unreadable file) fails before the case exists: the point starts from its
                        // deposit instead of failing. A failure once the case exists is the run's own.
                        try {
                            res = runFrom(warm);
                        } catch (const DeadlineReached&) {
                            throw;
                        } catch (const std::exception& e) {
                            if (fs::exists(dir)) throw;
                            std::cerr << "mixload: warning: point " << r->index << " could not start from " << warm.string()
                                      << " (" << e.what() << "); it starts from its deposit\n";
                            res = runFrom({});
                        }
                    }
                } else {
                    auto s = collapseSceneFor(c.sceneJson, r->params);
                    if (retry) s = retryScene(s);
                    res = runPoint<run::CollapseJob>(s, o.np, o.snapshots, home, r->index, deadline, run::runCollapse);
                }
                done = true;
            } catch (const DeadlineReached& e) {
                l.release(r->id);  // resumes in the next slice
                stopped = true;
                // A point kept from starting ran nothing: what it ran before was kept when it stopped.
                if (!dir.empty() && !dynamic_cast<const NotStarted*>(&e)) {
                    // What it ran outlives its directory (progress.hpp).
                    std::lock_guard<std::mutex> g(m);
                    try {
                        keepPointProgress(home, r->index, dir);
                    } catch (const std::exception& e) {
                        std::cerr << "mixload: warning: point " << r->index << "'s progress was not kept: " << e.what() << '\n';
                    }
                }
                return;
            } catch (const std::exception& e) {
                l.markFailed(r->id, e.what(), /*failed=*/r->attempts >= 2);
                if (r->attempts < 2) continue;
                if (!dir.empty()) {
                    // Failed for good: its kept progress would only be carried along.
                    std::lock_guard<std::mutex> g(m);
                    try {
                        dropFinishedProgress(home, r->index);
                    } catch (const std::exception& ex) {
                        std::cerr << "mixload: warning: point " << r->index << "'s kept progress was not dropped: " << ex.what() << '\n';
                    }
                }
            }
            if (done) {
                // The result is in its run directory now: a ledger that cannot take it (busy, disk
                // full) must not turn a finished run into a failed one or a rerun. The row stays
                // running; the next `campaign run` requeues it and takes the finished result.
                try {
                    l.markDone(r->id, store::runQois(c.scene, res), res.value("wall_seconds", 0.0),
                               res.value("core_seconds", res.value("wall_seconds", 0.0) * o.np),
                               res.value("run_dir", std::string()));
                } catch (const std::exception& e) {
                    std::cerr << "mixload: the ledger did not take point " << r->index << "'s finished result ("
                              << e.what() << "); it stays in " << res.value("run_dir", std::string())
                              << " and the next campaign run records it\n";
                    ++unrecorded;
                    return;
                }
            }
            std::lock_guard<std::mutex> g(m);
            if (done && !dir.empty()) {
                try {
                    dropFinishedProgress(home, r->index);
                } catch (const std::exception& e) {
                    std::cerr << "mixload: warning: point " << r->index << "'s kept progress was not dropped: " << e.what() << '\n';
                }
            }
            if (o.snapshots && done) {
                // The final fields outlive the run directory (one file beside the ledger).
                try {
                    store::keepCampaignFields(place.ledger(), place.name);
                } catch (const std::exception& e) {
                    std::cerr << "mixload: warning: the run's final fields were not kept: " << e.what() << '\n';
                }
            }
            ++finished;
            if (o.afterRun) o.afterRun();
            bar.update(double(finished) / total,
                       std::to_string(finished.load()) + "/" + std::to_string(total) + " runs");
        }
    };
    std::vector<std::thread> pool;
    for (int j = 0; j < o.jobs; ++j) pool.emplace_back(worker);
    for (auto& t : pool) t.join();
    bar.finish();
    const nlohmann::json counts = ledger->status(place.name);
    return {{"campaign", place.name}, {"counts", counts}, {"recovered", recovered},
            {"stopped_at_max_hours", stopped.load() && !stopRequested()}, {"stopped_on_request", stopRequested()},
            {"unrecorded_results", unrecorded.load()},
            {"wall_seconds", secondsSince(start)}};
}

}  // namespace mixload::experiments
