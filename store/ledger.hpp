// SPDX-License-Identifier: GPL-3.0-or-later
// The run ledger: one SQLite database (WAL journal, synchronous FULL) per campaign, holding the
// campaign's inputs and one row per design point with its status, attempts, timings, results and
// error text. Every change is one transaction, so a process killed at any instant leaves either the
// old row or the new one, never half of each; a driver that restarts finds runs it had marked
// running and may take them again (see claimNext).
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

struct sqlite3;

namespace mixload::store {

struct CampaignInfo {
    std::string name, scene, sceneHash, design, method, mesh, created, mixloadVersion, gitCommit;
    std::string rangesToml;   // the ranges file as given, kept verbatim
    nlohmann::json sceneJson; // the base scene (every input)
    std::uint64_t seed = 0;
};

struct LedgerRun {
    long id = 0;
    int index = 0;           // position in the design
    nlohmann::json params;   // physical inputs by name
    std::string status;      // queued | running | done | failed
    int attempts = 0;
    std::optional<double> wallSeconds, coreSeconds;
    nlohmann::json result;   // QoIs of a finished run
    std::string runDir, error, started, finished;
};

// A mixer run queued by `campaign replicate`: a design point again from a deposit of its own. It
// measures the label noise and is neither a training nor a hold-out point.
inline bool isReplicate(const LedgerRun& r) { return r.params.contains("initial_loading_kg"); }

// What a ledger keeps of a finished run's record (the full record stays in its run directory);
// kind: mixer | collapse.
nlohmann::json runQois(const std::string& kind, const nlohmann::json& result);

// The finished runs of a campaign, read from its ledger file in design order; InputError (naming
// the directory or the campaign) when there is no such ledger or campaign.
std::vector<LedgerRun> finishedCampaignRuns(const std::filesystem::path& ledger, const std::string& campaign);

class Ledger {
public:
    // Opens (creating if needed) the ledger file; throws std::runtime_error on SQLite errors.
    explicit Ledger(const std::filesystem::path& file);
    ~Ledger();
    Ledger(const Ledger&) = delete;
    Ledger& operator=(const Ledger&) = delete;

    // Creates the campaign and queues its points in one transaction; throws if it exists.
    void createCampaign(const CampaignInfo& info, const std::vector<nlohmann::json>& points);
    // Appends points (a design extension) after the existing ones, queued.
    void addPoints(const std::string& campaign, const std::vector<nlohmann::json>& points);
    std::optional<CampaignInfo> campaign(const std::string& name) const;
    // Gives the campaign another base scene and its runs the parameters (scene hashes) under it, in
    // one transaction (`campaign rebase`: a scene revision whose mesh is cell for cell the old one).
    void rebaseCampaign(const std::string& campaign, const nlohmann::json& sceneJson, const std::string& sceneHash,
                        const std::vector<std::pair<long, nlohmann::json>>& params);

    // Atomically takes the next run to do: a queued run, or (recover = true) one left "running" by
    // a driver that died; marks it running, counts the attempt. Runs with attempts >= maxAttempts
    // are not taken.
    // With `id`, only that run is taken (a driver that chooses its own next run, as a calibration).
    std::optional<LedgerRun> claimNext(const std::string& campaign, int maxAttempts, bool recover,
                                       std::optional<long> id = std::nullopt);
    void markDone(long id, const nlohmann::json& result, double wall, double core,
                  const std::string& runDir);
    // failed = true ends the run; false puts it back in the queue for another attempt.
    void markFailed(long id, const std::string& error, bool failed);
    // Gives a run back to the queue without counting the attempt (stopped by a deadline).
    void release(long id);
    // Puts runs marked running back in the queue without counting their interrupted attempt (a
    // fresh driver after a crash).
    int requeueRunning(const std::string& campaign);
    // Queues a run as never tried (attempts 0, no error): its next attempt is a first one again.
    void requeueAsFirst(long id);

    std::vector<LedgerRun> runs(const std::string& campaign) const;
    // Counts by status.
    nlohmann::json status(const std::string& campaign) const;
    // PRAGMA integrity_check == "ok".
    bool integrityOk() const;

private:
    void exec(const std::string& sql) const;
    void updateRun(const char* sql, long id);
    sqlite3* db_ = nullptr;
};

}  // namespace mixload::store
