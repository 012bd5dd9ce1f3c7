// SPDX-License-Identifier: GPL-3.0-or-later
#include "campaign/campaign_table.hpp"

#include "campaign/campaign.hpp"
#include "common/input_error.hpp"

namespace mixload::experiments {

surrogates::Point sceneInputs(const scene::MixerScene& s) {
    return {s.material.muS, s.material.muD, s.material.I0, s.material.grainDiameter, s.material.bulkDensity(),
            s.feedKgH,      s.rpm};
}

surrogates::Point mixerInputs(const nlohmann::json& base, const nlohmann::json& params) {
    return sceneInputs(mixerSceneFor(base, params));
}

std::optional<scene::MixerScene> campaignBaseScene(const nlohmann::json& base) {
    if (!base.is_object() || base.value("kind", std::string()) != "mixer") return std::nullopt;
    try {
        return mixerSceneFor(base, nlohmann::json::object());
    } catch (const std::exception&) {
        return std::nullopt;  // a scene renamed or retired since: what it would give is only left out
    }
}

surrogates::Table campaignTable(const std::string& name, const std::string& dir, nlohmann::json& provenance) {
    const CampaignPlace o{name, dir};
    std::unique_ptr<store::Ledger> l;
    const auto c = openCampaign(o, l);
    if (c.scene != "mixer") throw InputError("campaign", name, "a mixer campaign (surrogates model the loading)");
    provenance = {{"campaign", name},           {"ledger", o.ledger().string()},
                  {"design", c.design},         {"seed", c.seed},
                  {"base", c.sceneJson},        {"campaign_created", c.created},
                  {"campaign_mixload_version", c.mixloadVersion}, {"campaign_git_commit", c.gitCommit}};
    surrogates::Table t;
    for (const auto& r : l->runs(name)) {
        // As in the POD regression: a replicate counts its point twice, in training or hold-out; it
        // only says whether its point has one state (resolveTwoStates).
        const auto m = runQuantity(r, c.scene);
        if (!m) {
            ++(store::isReplicate(r) ? t.replicates : t.skipped);
            continue;
        }
        surrogates::Row row;
        row.id = r.params.value("scene_hash", std::to_string(r.index));
        row.x = mixerInputs(c.sceneJson, r.params);  // every input as the run saw it
        row.m = *m;
        const auto start = r.result.value("start", nlohmann::json::object());
        if (start.contains("deposit_kg")) row.depositKg = start["deposit_kg"].get<double>();
        if (store::isReplicate(r)) {
            row.depositKg = r.params["initial_loading_kg"].get<double>();
            ++t.replicates;
            t.replicateRuns.push_back(row);
        } else {
            t.rows.push_back(row);
        }
    }
    provenance["replicates_left_out"] = t.replicates;
    return t;
}

}  // namespace mixload::experiments
