// SPDX-License-Identifier: GPL-3.0-or-later
#include "campaign/progress.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <chrono>
#include <optional>
#include <vector>

#include <Eigen/Dense>

#include "common/atomic_file.hpp"
#include "common/clock.hpp"
#include "post/snapshots.hpp"
#include "run/foam_runner.hpp"
#include "run/monitor_state.hpp"
#include "run/run_dir.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {

fs::path progressFile(const fs::path& home) { return home / "progress.h5"; }

struct Kept {
    std::optional<store::SnapshotFile> file;
    nlohmann::json records = nlohmann::json::array();  // column i's point
};

Kept readProgress(const fs::path& home) {
    Kept k;
    if (!fs::exists(progressFile(home))) return k;
    k.file.emplace(progressFile(home));
    k.records = nlohmann::json::parse(k.file->provenance().at("progress_runs").get<std::string>());
    return k;
}

// Rewrites the progress file with `records` and their columns (the mesh from `source`), or removes
// it when none is left.
void writeProgress(const fs::path& home, const store::CaseFile* source, const nlohmann::json& records,
                   const std::vector<Eigen::VectorXd>& alphas, const std::vector<Eigen::VectorXd>& velocities) {
    const fs::path file = progressFile(home);
    if (records.empty()) {
        fs::remove(file);
        fs::remove(fs::path(file).replace_extension(".xmf"));
        return;
    }
    const auto n = static_cast<Eigen::Index>(alphas.size());
    Eigen::MatrixXd alpha(alphas.front().size(), n), U(velocities.front().size(), n);
    std::vector<double> indices;
    for (Eigen::Index i = 0; i < n; ++i) {
        alpha.col(i) = alphas[static_cast<size_t>(i)];
        U.col(i) = velocities[static_cast<size_t>(i)];
        indices.push_back(records[static_cast<size_t>(i)].at("index").get<double>());
    }
    store::writeDerivedSnapshots(*source, indices, {{"alpha", alpha}, {"U", U}},
                                 {{"kind", "campaign progress"}, {"progress_runs", records.dump()}}, file);
}

// The kept entries other than point `index`'s, column by column; held: whether it had one.
struct Others {
    nlohmann::json records = nlohmann::json::array();
    std::vector<Eigen::VectorXd> alphas, velocities;
    bool held = false;
};

Others othersThan(const Kept& kept, int index) {
    Others o;
    for (size_t i = 0; i < kept.records.size(); ++i) {
        if (kept.records[i].at("index").get<int>() == index) {
            o.held = true;
            continue;
        }
        o.records.push_back(kept.records[i]);
        o.alphas.push_back(kept.file->column("alpha", i));
        o.velocities.push_back(kept.file->column("U", i));
    }
    return o;
}

// How the run in runDir began: its own first start when it continues a lost run, else its start
// (a warm source) or the deposit its scene asks for.
nlohmann::json firstStart(const fs::path& runDir) {
    if (fs::exists(runDir / "start.json")) {
        const auto start = nlohmann::json::parse(readFile(runDir / "start.json"));
        return start.contains("first_start") ? start["first_start"] : start;
    }
    const auto scene = nlohmann::json::parse(readFile(runDir / "scene.json"));
    return {{"deposit_kg", scene.at("scene").value("initial_loading_kg", 0.0)}};
}

}  // namespace

double flowBefore(const nlohmann::json& start) {
    if (!start.is_object() || !start.contains("continues_run_dir")) return 0;
    return start.value("flow_before_s", start.value("source_time_s", 0.0));
}

double flowBeforeRun(const fs::path& runDir) {
    if (!fs::exists(runDir / "start.json")) return 0;
    return flowBefore(nlohmann::json::parse(readFile(runDir / "start.json")));
}

namespace {

// Removes a file (and its XDMF) when the scope ends, however it ends.
struct RemoveOnExit {
    fs::path file;
    ~RemoveOnExit() {
        std::error_code ec;
        fs::remove(file, ec);
        fs::remove(fs::path(file).replace_extension(".xmf"), ec);
    }
};

}  // namespace

nlohmann::json keepPointProgress(const fs::path& home, int index, const fs::path& runDir) {
    // A solver stopped at its deadline may have been writing: keep the latest whole time.
    run::setAsidePartialTime(runDir);
    const fs::path timeDir = run::latestTimeDir(runDir);
    if (timeDir.empty()) return nullptr;
    // The latest time alone (and the first, which the export always takes), in float64: a start
    // should hold what the run held.
    post::SnapshotExport e;
    e.runDir = runDir;
    e.output = home / ("progress-" + std::to_string(index) + ".export.h5");
    e.every = 1000000;
    e.fields = {"alpha", "U"};
    e.float64 = true;
    const RemoveOnExit cleanup{e.output};
    post::exportSnapshots(e);
    const store::SnapshotFile latest(e.output);
    const size_t last = latest.times().size() - 1;
    if (std::abs(latest.times().back() - run::latestTime(runDir)) > 1e-9 * std::max(1.0, latest.times().back()))
        throw std::runtime_error("the latest time of " + runDir.string() + " lacks alpha or U");
    // Every slice whole, the time spent after the kept time included: it was spent on the point.
    const auto slices = run::closedSlices(runDir, run::fileClockOf(timeDir), "kept progress: ended at its last written time");
    double wall = 0, core = 0;
    for (const auto& s : slices) wall += s.value("wall_seconds", 0.0), core += s.value("core_seconds", 0.0);
    const nlohmann::json record{{"index", index},
                                {"run_dir", runDir.filename().string()},
                                {"time_s", latest.times().back()},
                                {"flow_s", latest.times().back() + flowBeforeRun(runDir)},
                                {"wall_seconds", wall},
                                {"core_seconds", core},
                                {"slices", slices},
                                {"first_start", firstStart(runDir)},
                                {"monitor", run::keptMonitorState(timeDir)},
                                {"kept_utc", utcNow()}};
    const Kept kept = readProgress(home);
    Others o = kept.file && kept.file->meshFingerprint() == latest.meshFingerprint() ? othersThan(kept, index) : Others{};
    o.records.push_back(record);
    o.alphas.push_back(latest.column("alpha", last));
    o.velocities.push_back(latest.column("U", last));
    writeProgress(home, &latest, o.records, o.alphas, o.velocities);
    return {{"index", index}, {"time_s", record["time_s"]}, {"core_seconds", core}};
}

std::map<int, double> keptProgressFlow(const fs::path& home) {
    std::map<int, double> flow;
    for (const auto& r : readProgress(home).records)
        flow[r.at("index").get<int>()] = r.value("flow_s", r.at("time_s").get<double>());
    return flow;
}

void dropFinishedProgress(const fs::path& home, int index) {
    const Kept kept = readProgress(home);
    if (!kept.file) return;
    const Others o = othersThan(kept, index);
    if (!o.held) return;
    // The file is read whole above; its rewrite replaces it by rename.
    writeProgress(home, &*kept.file, o.records, o.alphas, o.velocities);
}

fs::path progressStart(const fs::path& home, int index, const fs::path& runDir) {
    if (fs::exists(runDir)) return {};  // the point resumes in its own directory
    const Kept kept = readProgress(home);
    for (size_t i = 0; i < kept.records.size(); ++i) {
        const auto& r = kept.records[i];
        if (r.at("index").get<int>() != index || r.value("run_dir", "") != runDir.filename().string()) continue;
        const fs::path file = home / "warm" / ("progress-" + std::to_string(index) + ".h5");
        fs::create_directories(file.parent_path());
        nlohmann::json prov{{"kind", "campaign progress"},
                            {"continues_run_dir", r.value("run_dir", "")},
                            {"first_start", r.value("first_start", nlohmann::json()).dump()},
                            {"slices", r.at("slices").dump()},
                            {"flow_before_s", r.value("flow_s", r.at("time_s")).dump()}};
        if (r.contains("monitor") && !r["monitor"].is_null()) prov["monitor"] = r["monitor"].dump();
        store::writeDerivedSnapshots(*kept.file, {r.at("time_s").get<double>()},
                                     {{"alpha", kept.file->column("alpha", i)}, {"U", kept.file->column("U", i)}},
                                     prov, file);
        return file;
    }
    return {};
}

}  // namespace mixload::experiments
