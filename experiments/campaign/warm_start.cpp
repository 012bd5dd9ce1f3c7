// SPDX-License-Identifier: GPL-3.0-or-later
#include "campaign/warm_start.hpp"

#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>

#include "campaign/design_space.hpp"
#include "common/input_error.hpp"
#include "doe/adaptive.hpp"
#include "store/campaign_fields.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

// Where a mixer design point starts under --warm-nearest: a finished run of the campaign (or of
// the pool), or empty (the deposit). A run serves from its directory, or, when the directory is no
// longer on this machine (a ledger carried over, a machine that came back empty), from its kept
// final fields, written out as a field file under <home>/warm. With five steady runs or more, a
// kriging model of their log loading predicts the point's loading, and the steady run whose
// loading is nearest that prediction is taken: the loading is what a start has to get right, and
// it varies far more along some inputs (the speed) than along others. With fewer, the nearest
// finished run in the design's unit cube, steady or stopped at its time cap, and also when no
// model fits the steady runs.
fs::path warmSourceFor(const std::vector<store::LedgerRun>& runs, const fs::path& home, const ParameterSpace& space,
                       const store::LedgerRun& r, const std::vector<WarmRun>& pool) {
    const auto at = unitOf(space, r);
    // Not from a replicate: one started from another deposit may sit in another steady state (a
    // factor 3.4 apart at v2c-holdout's 247 rpm point), the very thing it was run to show.
    std::vector<WarmRun> candidates;
    for (const auto& o : runs)
        if (o.index != r.index && !store::isReplicate(o)) candidates.push_back({o, home / "ledger.sqlite"});
    for (const auto& o : pool)
        if (!store::isReplicate(o.run)) candidates.push_back(o);
    // Where a candidate's start lies: its directory, else its kept fields, else nowhere.
    std::map<fs::path, std::set<int>> kept;  // ledger -> indices its fields file holds
    const auto keptIn = [&](const fs::path& ledger) -> const std::set<int>& {
        auto it = kept.find(ledger);
        if (it == kept.end()) it = kept.emplace(ledger, store::keptRunIndices(ledger)).first;
        return it->second;
    };
    const auto source = [&](const WarmRun& w) -> std::optional<WarmRun> {
        std::error_code ec;
        if (!w.run.runDir.empty() && fs::exists(fs::path(w.run.runDir) / "result.json", ec)) return w;
        if (keptIn(w.ledger).count(w.run.index)) return w;
        return std::nullopt;
    };
    Design units;
    std::vector<double> logM;
    std::vector<WarmRun> starts;
    std::optional<WarmRun> nearest;
    double nearestD2 = 1e300;
    for (const auto& c : candidates) {
        if (c.run.status != "done") continue;
        const auto s = source(c);
        if (!s) continue;
        auto u = unitOf(space, c.run);
        const double d2 = distance2(u, at);
        if (d2 < nearestD2) nearestD2 = d2, nearest = s;
        if (const auto m = runQuantity(c.run, "mixer")) {
            units.push_back(std::move(u));
            logM.push_back(std::log(*m));
            starts.push_back(*s);
        }
    }
    const auto path = [&](const std::optional<WarmRun>& w) -> fs::path {
        if (!w) return {};
        std::error_code ec;
        if (!w->run.runDir.empty() && fs::exists(fs::path(w->run.runDir) / "result.json", ec)) return w->run.runDir;
        // Named by the source campaign and the run's index, and written afresh each time (two pool
        // campaigns of one name in different places would otherwise share a stale file).
        const fs::path file = home / "warm" /
                              ("kept-" + w->ledger.parent_path().filename().string() + "-" + std::to_string(w->run.index) + ".h5");
        fs::create_directories(file.parent_path());
        return store::writeKeptRunFields(w->ledger, w->run.index, file) ? file : fs::path();
    };
    if (units.size() < 5) return path(nearest);
    double predicted = 0;
    try {
        predicted = mostUncertain(units, logM, {}, {at}, 1).picks.front().mean;
    } catch (const std::exception&) {
        return path(nearest);  // no model fits these runs: only the start is at stake, and it is recorded
    }
    size_t best = 0;
    for (size_t i = 1; i < logM.size(); ++i)
        if (std::abs(logM[i] - predicted) < std::abs(logM[best] - predicted)) best = i;
    return path(starts[best]);
}

std::vector<WarmRun> warmPool(const store::CampaignInfo& c, const std::vector<CampaignPlace>& from) {
    std::vector<WarmRun> pool;
    for (const auto& p : from) {
        std::unique_ptr<store::Ledger> l;
        const auto other = openCampaign(p, l);
        // A start's fields must be of the run's own mesh and scene: the same base, whatever the design.
        if (other.sceneJson != c.sceneJson)
            throw InputError("warm-from-campaign", p.name, "a campaign on the same base scene and mesh as " + c.name);
        // Its runs are placed in this campaign's design space, so they must carry its inputs.
        const auto names = [](const ParameterSpace& s) {
            std::set<std::string> n;
            for (const auto& q : s.params) n.insert(q.name);
            return n;
        };
        if (names(rangesOf(other, p.name)) != names(rangesOf(c, c.name)))
            throw InputError("warm-from-campaign", p.name, "a campaign that varies the same inputs as " + c.name);
        for (auto& r : l->runs(p.name))
            if (r.status == "done") pool.push_back({std::move(r), p.ledger()});
    }
    return pool;
}

fs::path campaignWarmSource(const CampaignPlace& place, int index, const std::vector<CampaignPlace>& from) {
    std::unique_ptr<store::Ledger> l;
    const auto c = openCampaign(place, l);
    const auto space = rangesOf(c, place.name);
    const auto runs = l->runs(place.name);
    const auto pool = warmPool(c, from);
    for (const auto& r : runs)
        if (r.index == index) return warmSourceFor(runs, place.home(), space, r, pool);
    throw InputError("index", std::to_string(index), "a point of campaign " + place.name);
}

}  // namespace mixload::experiments
