// SPDX-License-Identifier: GPL-3.0-or-later
#include "store/ledger.hpp"

#include <stdexcept>

#include <sqlite3.h>

#include "common/clock.hpp"
#include "common/input_error.hpp"

namespace mixload::store {

namespace {

// One prepared statement; bind() takes 1-based positions as SQLite does.
class Stmt {
public:
    Stmt(sqlite3* db, const std::string& sql) : db_(db) {
        if (sqlite3_prepare_v2(db, sql.c_str(), -1, &s_, nullptr) != SQLITE_OK)
            throw std::runtime_error(std::string("ledger: ") + sqlite3_errmsg(db) + " in: " + sql);
    }
    ~Stmt() { sqlite3_finalize(s_); }
    Stmt& bind(int i, const std::string& v) {
        sqlite3_bind_text(s_, i, v.c_str(), -1, SQLITE_TRANSIENT);
        return *this;
    }
    Stmt& bind(int i, long long v) {
        sqlite3_bind_int64(s_, i, v);
        return *this;
    }
    Stmt& bind(int i, double v) {
        sqlite3_bind_double(s_, i, v);
        return *this;
    }
    // true while there is a row
    bool step() {
        const int rc = sqlite3_step(s_);
        if (rc == SQLITE_ROW) return true;
        if (rc == SQLITE_DONE) return false;
        throw std::runtime_error(std::string("ledger: ") + sqlite3_errmsg(db_));
    }
    std::string text(int c) const {
        const auto* p = sqlite3_column_text(s_, c);
        return p ? reinterpret_cast<const char*>(p) : "";
    }
    long long integer(int c) const { return sqlite3_column_int64(s_, c); }
    std::optional<double> real(int c) const {
        if (sqlite3_column_type(s_, c) == SQLITE_NULL) return std::nullopt;
        return sqlite3_column_double(s_, c);
    }

private:
    sqlite3* db_;
    sqlite3_stmt* s_ = nullptr;
};

// BEGIN IMMEDIATE ... COMMIT, rolled back if the scope is left by an exception.
class Transaction {
public:
    explicit Transaction(sqlite3* db) : db_(db) { run("BEGIN IMMEDIATE"); }
    ~Transaction() {
        if (!done_) sqlite3_exec(db_, "ROLLBACK", nullptr, nullptr, nullptr);
    }
    void commit() {
        run("COMMIT");
        done_ = true;
    }

private:
    void run(const char* sql) {
        char* err = nullptr;
        if (sqlite3_exec(db_, sql, nullptr, nullptr, &err) != SQLITE_OK) {
            const std::string m = err ? err : "?";
            sqlite3_free(err);
            throw std::runtime_error(std::string("ledger: ") + sql + ": " + m);
        }
    }
    sqlite3* db_;
    bool done_ = false;
};

const char* kRunColumns =
    "id, idx, params, status, attempts, wall_seconds, core_seconds, result, run_dir, error, "
    "started, finished";

LedgerRun readRun(const Stmt& s) {
    LedgerRun r;
    r.id = static_cast<long>(s.integer(0));
    r.index = static_cast<int>(s.integer(1));
    r.params = nlohmann::json::parse(s.text(2));
    r.status = s.text(3);
    r.attempts = static_cast<int>(s.integer(4));
    r.wallSeconds = s.real(5);
    r.coreSeconds = s.real(6);
    const std::string res = s.text(7);
    r.result = res.empty() ? nlohmann::json() : nlohmann::json::parse(res);
    r.runDir = s.text(8);
    r.error = s.text(9);
    r.started = s.text(10);
    r.finished = s.text(11);
    return r;
}

}  // namespace

nlohmann::json runQois(const std::string& kind, const nlohmann::json& r) {
    const std::vector<const char*> keys =
        kind == "mixer" ? std::vector<const char*>{"loading_kg", "loading_std_kg", "steady", "steady_time_s",
                                                   "outflow_kg_h", "powder_leak_kg_h", "powder_balance_ok",
                                                   "final_loading_kg", "end_time_s", "cells", "start",
                                                   // the label protocol's judgement (fullcfd/run/label_protocol)
                                                   "protocol", "label", "not_label_because", "settled_residence_times",
                                                   "level_change_seen", "dense_share", "level_m", "dense_loading_kg"}
                        : std::vector<const char*>{"runout_star", "height_star", "stopped_by", "t_star",
                                                   "end_time", "powder_mass_error", "cells"};
    nlohmann::json q = nlohmann::json::object();
    for (const char* k : keys)
        if (r.contains(k)) q[k] = r[k];
    return q;
}

std::vector<LedgerRun> finishedCampaignRuns(const std::filesystem::path& ledger, const std::string& campaign) {
    if (!std::filesystem::exists(ledger))
        throw InputError("dir", ledger.parent_path().string(), "a campaign directory with a ledger.sqlite");
    const Ledger l(ledger);
    if (!l.campaign(campaign)) throw InputError("campaign", campaign, "a campaign of " + ledger.string());
    std::vector<LedgerRun> out;
    for (auto& r : l.runs(campaign))
        if (r.status == "done") out.push_back(std::move(r));
    return out;
}

Ledger::Ledger(const std::filesystem::path& file) {
    if (!file.parent_path().empty()) std::filesystem::create_directories(file.parent_path());
    if (sqlite3_open(file.c_str(), &db_) != SQLITE_OK) {
        const std::string m = db_ ? sqlite3_errmsg(db_) : "out of memory";
        sqlite3_close(db_);
        throw std::runtime_error("ledger: cannot open " + file.string() + ": " + m);
    }
    sqlite3_busy_timeout(db_, 30000);
    // WAL + synchronous FULL: a committed transaction survives a kill or power loss; a killed
    // writer's partial transaction is rolled back on the next open.
    exec("PRAGMA journal_mode=WAL");
    exec("PRAGMA synchronous=FULL");
    exec("PRAGMA foreign_keys=ON");
    exec("CREATE TABLE IF NOT EXISTS campaigns ("
         " name TEXT PRIMARY KEY, scene TEXT NOT NULL, scene_hash TEXT NOT NULL,"
         " scene_json TEXT NOT NULL, ranges_toml TEXT NOT NULL, design TEXT NOT NULL,"
         " seed INTEGER NOT NULL, method TEXT, mesh TEXT, created TEXT NOT NULL,"
         " mixload_version TEXT NOT NULL, git_commit TEXT NOT NULL)");
    exec("CREATE TABLE IF NOT EXISTS runs ("
         " id INTEGER PRIMARY KEY, campaign TEXT NOT NULL REFERENCES campaigns(name),"
         " idx INTEGER NOT NULL, params TEXT NOT NULL,"
         " status TEXT NOT NULL CHECK (status IN ('queued','running','done','failed')),"
         " attempts INTEGER NOT NULL DEFAULT 0, wall_seconds REAL, core_seconds REAL,"
         " result TEXT, run_dir TEXT, error TEXT, started TEXT, finished TEXT,"
         " UNIQUE (campaign, idx))");
}

Ledger::~Ledger() { sqlite3_close(db_); }

void Ledger::exec(const std::string& sql) const {
    char* err = nullptr;
    if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &err) != SQLITE_OK) {
        const std::string m = err ? err : "?";
        sqlite3_free(err);
        throw std::runtime_error("ledger: " + m + " in: " + sql);
    }
}

void Ledger::createCampaign(const CampaignInfo& c, const std::vector<nlohmann::json>& points) {
    Transaction tx(db_);
    {
        Stmt s(db_, "SELECT 1 FROM campaigns WHERE name = ?");
        s.bind(1, c.name);
        if (s.step()) throw std::runtime_error("campaign " + c.name + " exists already");
    }
    Stmt s(db_,
           "INSERT INTO campaigns (name, scene, scene_hash, scene_json, ranges_toml, design, seed,"
           " method, mesh, created, mixload_version, git_commit) VALUES (?,?,?,?,?,?,?,?,?,?,?,?)");
    s.bind(1, c.name).bind(2, c.scene).bind(3, c.sceneHash).bind(4, c.sceneJson.dump())
        .bind(5, c.rangesToml).bind(6, c.design).bind(7, static_cast<long long>(c.seed))
        .bind(8, c.method).bind(9, c.mesh).bind(10, c.created.empty() ? utcNow() : c.created)
        .bind(11, c.mixloadVersion).bind(12, c.gitCommit);
    s.step();
    for (size_t i = 0; i < points.size(); ++i) {
        Stmt p(db_, "INSERT INTO runs (campaign, idx, params, status) VALUES (?,?,?,'queued')");
        p.bind(1, c.name).bind(2, static_cast<long long>(i)).bind(3, points[i].dump());
        p.step();
    }
    tx.commit();
}

void Ledger::addPoints(const std::string& campaign, const std::vector<nlohmann::json>& points) {
    Transaction tx(db_);
    long long next = 0;
    {
        Stmt s(db_, "SELECT COALESCE(MAX(idx) + 1, 0) FROM runs WHERE campaign = ?");
        s.bind(1, campaign);
        if (s.step()) next = s.integer(0);
    }
    for (const auto& pt : points) {
        Stmt p(db_, "INSERT INTO runs (campaign, idx, params, status) VALUES (?,?,?,'queued')");
        p.bind(1, campaign).bind(2, next++).bind(3, pt.dump());
        p.step();
    }
    tx.commit();
}

void Ledger::rebaseCampaign(const std::string& campaign, const nlohmann::json& sceneJson, const std::string& sceneHash,
                            const std::vector<std::pair<long, nlohmann::json>>& params) {
    Transaction tx(db_);
    Stmt c(db_, "UPDATE campaigns SET scene_json = ?, scene_hash = ? WHERE name = ?");
    c.bind(1, sceneJson.dump()).bind(2, sceneHash).bind(3, campaign);
    c.step();
    for (const auto& [id, p] : params) {
        Stmt r(db_, "UPDATE runs SET params = ? WHERE id = ? AND campaign = ?");
        r.bind(1, p.dump()).bind(2, static_cast<long long>(id)).bind(3, campaign);
        r.step();
    }
    tx.commit();
}

std::optional<CampaignInfo> Ledger::campaign(const std::string& name) const {
    Stmt s(db_,
           "SELECT name, scene, scene_hash, scene_json, ranges_toml, design, seed, method, mesh,"
           " created, mixload_version, git_commit FROM campaigns WHERE name = ?");
    s.bind(1, name);
    if (!s.step()) return std::nullopt;
    CampaignInfo c;
    c.name = s.text(0);
    c.scene = s.text(1);
    c.sceneHash = s.text(2);
    c.sceneJson = nlohmann::json::parse(s.text(3));
    c.rangesToml = s.text(4);
    c.design = s.text(5);
    c.seed = static_cast<std::uint64_t>(s.integer(6));
    c.method = s.text(7);
    c.mesh = s.text(8);
    c.created = s.text(9);
    c.mixloadVersion = s.text(10);
    c.gitCommit = s.text(11);
    return c;
}

std::optional<LedgerRun> Ledger::claimNext(const std::string& campaign, int maxAttempts,
                                           bool recover, std::optional<long> id) {
    Transaction tx(db_);
    std::optional<LedgerRun> r;
    {
        Stmt s(db_, std::string("SELECT ") + kRunColumns +
                        " FROM runs WHERE campaign = ? AND attempts < ? AND (status = 'queued'" +
                        (recover ? " OR status = 'running'" : "") + ")" + (id ? " AND id = ?" : "") +
                        " ORDER BY idx LIMIT 1");
        s.bind(1, campaign).bind(2, static_cast<long long>(maxAttempts));
        if (id) s.bind(3, static_cast<long long>(*id));
        if (s.step()) r = readRun(s);
    }
    if (!r) return std::nullopt;
    Stmt u(db_, "UPDATE runs SET status = 'running', attempts = attempts + 1, started = ?,"
                " error = NULL WHERE id = ?");
    u.bind(1, utcNow()).bind(2, static_cast<long long>(r->id));
    u.step();
    tx.commit();
    r->status = "running";
    r->attempts += 1;
    return r;
}

void Ledger::markDone(long id, const nlohmann::json& result, double wall, double core,
                      const std::string& runDir) {
    Transaction tx(db_);
    Stmt u(db_, "UPDATE runs SET status = 'done', result = ?, wall_seconds = ?, core_seconds = ?,"
                " run_dir = ?, finished = ?, error = NULL WHERE id = ?");
    u.bind(1, result.dump()).bind(2, wall).bind(3, core).bind(4, runDir).bind(5, utcNow())
        .bind(6, static_cast<long long>(id));
    u.step();
    tx.commit();
}

void Ledger::markFailed(long id, const std::string& error, bool failed) {
    Transaction tx(db_);
    Stmt u(db_, "UPDATE runs SET status = ?, error = ?, finished = ? WHERE id = ?");
    u.bind(1, std::string(failed ? "failed" : "queued")).bind(2, error).bind(3, utcNow())
        .bind(4, static_cast<long long>(id));
    u.step();
    tx.commit();
}

// One statement on one run: atomic as it stands (SQLite's autocommit).
void Ledger::updateRun(const char* sql, long id) {
    Stmt u(db_, sql);
    u.bind(1, static_cast<long long>(id));
    u.step();
}

void Ledger::release(long id) {
    updateRun("UPDATE runs SET status = 'queued', attempts = MAX(attempts - 1, 0) WHERE id = ?", id);
}

int Ledger::requeueRunning(const std::string& campaign) {
    Transaction tx(db_);
    // The interrupted attempt does not count: the run resumes in its own directory.
    Stmt u(db_, "UPDATE runs SET status = 'queued', attempts = MAX(attempts - 1, 0)"
                " WHERE campaign = ? AND status = 'running'");
    u.bind(1, campaign);
    u.step();
    const int n = sqlite3_changes(db_);
    tx.commit();
    return n;
}

void Ledger::requeueAsFirst(long id) {
    updateRun("UPDATE runs SET status = 'queued', attempts = 0, error = NULL, finished = NULL WHERE id = ?", id);
}

std::vector<LedgerRun> Ledger::runs(const std::string& campaign) const {
    Stmt s(db_, std::string("SELECT ") + kRunColumns + " FROM runs WHERE campaign = ? ORDER BY idx");
    s.bind(1, campaign);
    std::vector<LedgerRun> out;
    while (s.step()) out.push_back(readRun(s));
    return out;
}

nlohmann::json Ledger::status(const std::string& campaign) const {
    nlohmann::json j{{"queued", 0}, {"running", 0}, {"done", 0}, {"failed", 0}};
    Stmt s(db_, "SELECT status, COUNT(*) FROM runs WHERE campaign = ? GROUP BY status");
    s.bind(1, campaign);
    while (s.step()) j[s.text(0)] = s.integer(1);
    return j;
}

bool Ledger::integrityOk() const {
    Stmt s(db_, "PRAGMA integrity_check");
    return s.step() && s.text(0) == "ok";
}

}  // namespace mixload::store
