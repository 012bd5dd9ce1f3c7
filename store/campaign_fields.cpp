// SPDX-License-Identifier: GPL-3.0-or-later
#include "store/campaign_fields.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::store {

namespace fs = std::filesystem;

namespace {

struct Kept {
    std::optional<SnapshotFile> file;
    bool hasMean = false;  // the file has an alpha_window_mean field
    std::map<int, std::pair<size_t, nlohmann::json>> byIndex;  // run index -> (column, record)
};

bool hasField(const SnapshotFile& f, const std::string& name) {
    const auto names = f.fields();
    return std::find(names.begin(), names.end(), name) != names.end();
}

Kept readKept(const fs::path& ledger) {
    Kept k;
    const fs::path f = campaignFieldsFile(ledger);
    if (!fs::exists(f)) return k;
    k.file.emplace(f);
    k.hasMean = hasField(*k.file, "alpha_window_mean");
    const auto runs = nlohmann::json::parse(k.file->provenance().at("kept_runs").get<std::string>());
    for (size_t i = 0; i < runs.size(); ++i) k.byIndex[runs[i].at("index").get<int>()] = {i, runs[i]};
    return k;
}

double bulkDensityOf(const CaseFile& f) {
    const auto p = f.params();
    return p.contains("material.bulk_density_kg_m3") ? p["material.bulk_density_kg_m3"].get<double>() : 0.0;
}

bool hasVelocity(const SnapshotFile& f) { return hasField(f, "U"); }

// The window mean kept for a run, when the file holds a whole one: a column of NaN stands for a run
// kept without it (found in v2c-holdout's file beside records that claimed one).
std::optional<Eigen::VectorXd> keptWindowMean(const Kept& k, const std::pair<size_t, nlohmann::json>& kept) {
    if (kept.second.value("window_times", 0) <= 0 || !k.hasMean) return std::nullopt;
    Eigen::VectorXd m = k.file->column("alpha_window_mean", kept.first);
    if (!m.allFinite()) return std::nullopt;
    return m;
}

// Whether the kept file holds all a run directory would give: the velocity, and the window mean
// (as keptWindowMean read it) or the finding that the run's snapshots hold too few times for one.
bool keptWhole(const nlohmann::json& record, const std::optional<Eigen::VectorXd>& mean) {
    return record.value("velocity", false) && record.contains("window_times") &&
           (record.value("window_times", 0) == 0 || mean.has_value());
}

bool hasSnapshots(const LedgerRun& r) { return !r.runDir.empty() && fs::exists(fs::path(r.runDir) / "snapshots.h5"); }

// The mean powder fraction over the stored times of the run's final window (result.json's
// "window", the steady test's), with how many times it averages; none below three.
std::pair<Eigen::VectorXd, int> windowMean(const SnapshotFile& f, const LedgerRun& r) {
    const fs::path result = fs::path(r.runDir) / "result.json";
    if (!fs::exists(result)) return {};
    const auto j = nlohmann::json::parse(readFile(result), nullptr, false);
    if (j.is_discarded() || !j.contains("window") || !j["window"].is_number()) return {};
    const auto& times = f.times();
    const double from = times.back() - j["window"].get<double>();
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(f.cells()));
    int n = 0;
    for (size_t i = 0; i < times.size(); ++i)
        if (times[i] >= from) sum += f.column("alpha", i), ++n;
    if (n < 3) return {};
    return {sum / n, n};
}

}  // namespace

fs::path campaignFieldsFile(const fs::path& ledger) { return ledger.parent_path() / "fields.h5"; }

nlohmann::json keepCampaignFields(const fs::path& ledger, const std::string& campaign) {
    const auto runs = finishedCampaignRuns(ledger, campaign);
    const Kept kept = readKept(ledger);
    const bool keptU = kept.file && hasVelocity(*kept.file);
    std::vector<double> indices;
    std::vector<Eigen::VectorXd> alphas, velocities, means;
    nlohmann::json records = nlohmann::json::array();
    std::optional<SnapshotFile> source;
    if (kept.file) source.emplace(kept.file->path());
    int added = 0, upgraded = 0, meansAdded = 0;
    // The MRF zones travel with the mesh (the reduced steady model needs them): a kept file written
    // before they were kept takes them from any run directory whose snapshots have them.
    bool zonesAdded = false;
    if (source && source->mrfZones().empty())
        for (const auto& r : runs) {
            if (!hasSnapshots(r)) continue;
            const SnapshotFile f(fs::path(r.runDir) / "snapshots.h5");
            if (f.meshFingerprint() != source->meshFingerprint() || f.mrfZones().empty()) continue;
            source.emplace(f.path());
            zonesAdded = true;
            break;
        }
    const auto cells = [&] { return source ? source->cells() : 0; };
    for (const auto& r : runs) {
        const auto it = kept.byIndex.find(r.index);
        const bool inKept = it != kept.byIndex.end();
        const bool keptWithU = inKept && it->second.second.value("velocity", false);
        const auto keptMean = inKept ? keptWindowMean(kept, it->second) : std::nullopt;
        const bool keptWithMean = keptMean.has_value();
        // A kept run is read again from its directory only for what the file lacks and the directory has.
        if (inKept && (!hasSnapshots(r) || keptWhole(it->second.second, keptMean))) {
            indices.push_back(r.index);
            alphas.push_back(kept.file->column("alpha", it->second.first));
            velocities.push_back(keptU ? kept.file->column("U", it->second.first)
                                       : Eigen::VectorXd::Constant(3 * cells(), std::nan("")));
            means.push_back(keptMean ? *keptMean : Eigen::VectorXd::Constant(cells(), std::nan("")));
            records.push_back(it->second.second);
            continue;
        }
        if (!hasSnapshots(r)) continue;
        // A new run, or a kept one whose directory still holds the velocity the file lacks.
        const SnapshotFile f(fs::path(r.runDir) / "snapshots.h5");
        if (!source) source.emplace(f.path());
        if (f.meshFingerprint() != source->meshFingerprint())
            throw InputError("campaign", campaign, "runs on one mesh (" + f.path().string() + " differs)");
        const size_t last = f.times().size() - 1;
        const bool withU = hasVelocity(f);
        auto [mean, windowTimes] = windowMean(f, r);
        indices.push_back(r.index);
        alphas.push_back(f.column("alpha", last));
        velocities.push_back(withU ? f.column("U", last) : Eigen::VectorXd::Constant(3 * cells(), std::nan("")));
        means.push_back(windowTimes > 0 ? mean : Eigen::VectorXd::Constant(cells(), std::nan("")));
        records.push_back({{"index", r.index},
                           {"scene_hash", r.params.value("scene_hash", std::string())},
                           {"time_s", f.times().back()},
                           {"bulk_density_kg_m3", bulkDensityOf(f)},
                           {"velocity", withU},
                           {"window_times", windowTimes}});
        // A kept run re-read without finding anything new changes nothing: no rewrite for it.
        if (!inKept) ++added;
        else if (withU && !keptWithU) ++upgraded;
        else if (windowTimes > 0 && !keptWithMean) ++meansAdded;
    }
    const fs::path file = campaignFieldsFile(ledger);
    if (alphas.empty()) throw InputError("campaign", campaign, "finished runs with snapshots to keep (campaign run --snapshots)");
    if (added + upgraded + meansAdded > 0 || zonesAdded) {
        const auto n = static_cast<Eigen::Index>(alphas.size());
        Eigen::MatrixXd alpha(alphas.front().size(), n), U(3 * alphas.front().size(), n), mean(alphas.front().size(), n);
        for (Eigen::Index i = 0; i < n; ++i) {
            alpha.col(i) = alphas[static_cast<size_t>(i)];
            U.col(i) = velocities[static_cast<size_t>(i)];
            mean.col(i) = means[static_cast<size_t>(i)];
        }
        writeDerivedSnapshots(*source, indices, {{"alpha", alpha}, {"U", U}, {"alpha_window_mean", mean}},
                              {{"kind", "campaign final fields"},
                               {"campaign", campaign},
                               {"kept_runs", records.dump()}},
                              file);
    }
    return {{"file", file.string()}, {"kept", alphas.size()}, {"added", added}, {"velocity_added", upgraded},
            {"window_mean_added", meansAdded},
            {"zones_added", zonesAdded}};
}

std::set<int> keptRunIndices(const fs::path& ledger) {
    std::set<int> out;
    for (const auto& [index, kept] : readKept(ledger).byIndex) out.insert(index);
    return out;
}

bool writeKeptRunFields(const fs::path& ledger, int index, const fs::path& file) {
    const Kept kept = readKept(ledger);
    const auto it = kept.byIndex.find(index);
    if (it == kept.byIndex.end()) return false;
    const auto& [column, record] = it->second;
    std::vector<std::pair<std::string, Eigen::MatrixXd>> fields{{"alpha", kept.file->column("alpha", column)}};
    if (record.value("velocity", false) && hasVelocity(*kept.file)) {
        Eigen::VectorXd U = kept.file->column("U", column);
        if (U.allFinite()) fields.emplace_back("U", std::move(U));
    }
    writeDerivedSnapshots(*kept.file, {record.value("time_s", 0.0)}, fields,
                          {{"kind", "kept run fields"}, {"kept_from", campaignFieldsFile(ledger).string()},
                           {"run_index", index}},
                          file);
    return true;
}

FinalFields campaignFinalFields(const fs::path& ledger, const std::string& campaign) {
    const auto runs = finishedCampaignRuns(ledger, campaign);
    const Kept kept = readKept(ledger);
    FinalFields out;
    std::string fingerprint;
    bool sourceHasZones = false;
    const auto sameMesh = [&](const SnapshotFile& f) {
        if (fingerprint.empty()) {
            fingerprint = f.meshFingerprint(), out.meshSource = f.path();
            sourceHasZones = !f.mrfZones().empty();
        } else if (f.meshFingerprint() != fingerprint) {
            throw InputError("campaign", campaign, "runs on one mesh (" + f.path().string() + " differs)");
        } else if (!sourceHasZones && !f.mrfZones().empty()) {
            // Files written since the MRF zones are kept carry them: the reduced steady model needs them.
            out.meshSource = f.path(), sourceHasZones = true;
        }
    };
    for (const auto& r : runs) {
        // The kept file gives what the run directory would (checked to every digit) in one read, so
        // it serves when it holds the run whole (velocity and window mean); the directory serves the rest.
        const auto it = kept.byIndex.find(r.index);
        const bool inKept = it != kept.byIndex.end();
        const auto keptMean = inKept ? keptWindowMean(kept, it->second) : std::nullopt;
        if (hasSnapshots(r) && !(inKept && keptWhole(it->second.second, keptMean))) {
            const SnapshotFile f(fs::path(r.runDir) / "snapshots.h5");
            sameMesh(f);
            const size_t last = f.times().size() - 1;
            auto [mean, times] = windowMean(f, r);
            out.runs.push_back({r, f.column("alpha", last), hasVelocity(f) ? f.column("U", last) : Eigen::VectorXd(), bulkDensityOf(f),
                                std::move(mean), times});
        } else if (inKept) {
            sameMesh(*kept.file);
            const bool withU = it->second.second.value("velocity", false);
            out.runs.push_back({r, kept.file->column("alpha", it->second.first),
                                withU ? kept.file->column("U", it->second.first) : Eigen::VectorXd(),
                                it->second.second.value("bulk_density_kg_m3", 0.0), keptMean.value_or(Eigen::VectorXd()),
                                keptMean ? it->second.second.value("window_times", 0) : 0});
        }
    }
    if (out.runs.empty())
        throw InputError("campaign", campaign,
                         "a campaign whose finished runs kept snapshots (campaign run --snapshots) or fields (" +
                             campaignFieldsFile(ledger).string() + ")");
    return out;
}

}  // namespace mixload::store
