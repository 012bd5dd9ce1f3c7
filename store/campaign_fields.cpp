// SPDX-License-Identifier: GPL-3.0-or-later
#include "store/campaign_fields.hpp"

#include <map>
#include <optional>

#include "common/input_error.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::store {

namespace fs = std::filesystem;

namespace {

struct Kept {
    std::optional<SnapshotFile> file;
    std::map<int, std::pair<size_t, nlohmann::json>> byIndex;  // run index -> (column, record)
};

Kept readKept(const fs::path& ledger) {
    Kept k;
    const fs::path f = campaignFieldsFile(ledger);
    if (!fs::exists(f)) return k;
    k.file.emplace(f);
    const auto runs = nlohmann::json::parse(k.file->provenance().at("kept_runs").get<std::string>());
    for (size_t i = 0; i < runs.size(); ++i) k.byIndex[runs[i].at("index").get<int>()] = {i, runs[i]};
    return k;
}

double bulkDensityOf(const CaseFile& f) {
    const auto p = f.params();
    return p.contains("material.bulk_density_kg_m3") ? p["material.bulk_density_kg_m3"].get<double>() : 0.0;
}

bool hasSnapshots(const LedgerRun& r) { return !r.runDir.empty() && fs::exists(fs::path(r.runDir) / "snapshots.h5"); }

}  // namespace

fs::path campaignFieldsFile(const fs::path& ledger) { return ledger.parent_path() / "fields.h5"; }

nlohmann::json keepCampaignFields(const fs::path& ledger, const std::string& campaign) {
    const auto runs = finishedCampaignRuns(ledger, campaign);
    const Kept kept = readKept(ledger);
    std::vector<double> indices;
    std::vector<Eigen::VectorXd> columns;
    nlohmann::json records = nlohmann::json::array();
    std::optional<SnapshotFile> source;
    if (kept.file) source.emplace(kept.file->path());
    int added = 0;
    for (const auto& r : runs) {
        const auto it = kept.byIndex.find(r.index);
        if (it != kept.byIndex.end()) {
            indices.push_back(r.index);
            columns.push_back(kept.file->column("alpha", it->second.first));
            records.push_back(it->second.second);
            continue;
        }
        if (!hasSnapshots(r)) continue;
        const SnapshotFile f(fs::path(r.runDir) / "snapshots.h5");
        if (!source) source.emplace(f.path());
        if (f.meshFingerprint() != source->meshFingerprint())
            throw InputError("campaign", campaign, "runs on one mesh (" + f.path().string() + " differs)");
        indices.push_back(r.index);
        columns.push_back(f.column("alpha", f.times().size() - 1));
        records.push_back({{"index", r.index},
                           {"scene_hash", r.params.value("scene_hash", std::string())},
                           {"time_s", f.times().back()},
                           {"bulk_density_kg_m3", bulkDensityOf(f)}});
        ++added;
    }
    const fs::path file = campaignFieldsFile(ledger);
    if (columns.empty()) throw InputError("campaign", campaign, "finished runs with snapshots to keep (campaign run --snapshots)");
    if (added > 0) {
        Eigen::MatrixXd alpha(columns.front().size(), static_cast<Eigen::Index>(columns.size()));
        for (size_t i = 0; i < columns.size(); ++i) alpha.col(static_cast<Eigen::Index>(i)) = columns[i];
        writeDerivedSnapshots(*source, indices, {{"alpha", alpha}},
                              {{"kind", "campaign final fields"},
                               {"campaign", campaign},
                               {"kept_runs", records.dump()}},
                              file);
    }
    return {{"file", file.string()}, {"kept", columns.size()}, {"added", added}};
}

FinalFields campaignFinalFields(const fs::path& ledger, const std::string& campaign) {
    const auto runs = finishedCampaignRuns(ledger, campaign);
    const Kept kept = readKept(ledger);
    FinalFields out;
    std::string fingerprint;
    const auto sameMesh = [&](const SnapshotFile& f) {
        if (fingerprint.empty()) fingerprint = f.meshFingerprint(), out.meshSource = f.path();
        else if (f.meshFingerprint() != fingerprint)
            throw InputError("campaign", campaign, "runs on one mesh (" + f.path().string() + " differs)");
    };
    for (const auto& r : runs) {
        if (hasSnapshots(r)) {
            const SnapshotFile f(fs::path(r.runDir) / "snapshots.h5");
            sameMesh(f);
            out.runs.push_back({r, f.column("alpha", f.times().size() - 1), bulkDensityOf(f)});
        } else if (const auto it = kept.byIndex.find(r.index); it != kept.byIndex.end()) {
            sameMesh(*kept.file);
            out.runs.push_back({r, kept.file->column("alpha", it->second.first),
                                it->second.second.value("bulk_density_kg_m3", 0.0)});
        }
    }
    if (out.runs.empty())
        throw InputError("campaign", campaign,
                         "a campaign whose finished runs kept snapshots (campaign run --snapshots) or fields (" +
                             campaignFieldsFile(ledger).string() + ")");
    return out;
}

}  // namespace mixload::store
