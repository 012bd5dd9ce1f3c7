// SPDX-License-Identifier: GPL-3.0-or-later
#include "table.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "common/input_error.hpp"

namespace mixload::surrogates {

namespace {

double numberOr(const std::string& s, double fallback) {
    try {
        return std::stod(s);
    } catch (const std::exception&) {
        return fallback;
    }
}

// CSV fields with "quoted, fields" and "" escapes, as the campaign export writes them.
std::vector<std::string> splitCsv(const std::string& line) {
    std::vector<std::string> out;
    std::string cur;
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cur += '"', ++i;
            else if (c == '"') quoted = false;
            else cur += c;
        } else if (c == '"') {
            quoted = true;
        } else if (c == ',') {
            out.push_back(cur);
            cur.clear();
        } else if (c != '\r') {
            cur += c;
        }
    }
    out.push_back(cur);
    return out;
}

}  // namespace

namespace {

struct Csv {
    std::map<std::string, size_t> col;
    std::vector<std::vector<std::string>> rows;
    nlohmann::json provenance = nlohmann::json::object();
};

// The campaign export's first line; anything else (or a base that is not JSON) gives nothing.
nlohmann::json exportProvenance(const std::string& line) {
    static const std::regex head(
        R"(^# campaign (\S+), scene (\S+), design (\S+), seed (\d+), base (\{.*\}), created (\S+) by mixload (\S+) \((\S*)\)\s*$)");
    std::smatch m;
    if (!std::regex_match(line, m, head)) return nlohmann::json::object();
    auto base = nlohmann::json::parse(m[5].str(), nullptr, false);
    if (base.is_discarded() || !base.is_object()) return nlohmann::json::object();
    return {{"campaign", m[1].str()},
            {"design", m[3].str()},
            {"seed", std::stoull(m[4].str())},
            {"base", base},
            {"campaign_created", m[6].str()},
            {"campaign_mixload_version", m[7].str()},
            {"campaign_git_commit", m[8].str()}};
}

Csv parseCsv(const std::filesystem::path& csv) {
    std::ifstream is(csv);
    if (!is) throw InputError("table", csv.string(), "a readable CSV file");
    Csv c;
    std::string line;
    bool header = false;
    while (std::getline(is, line)) {
        if (!header && c.provenance.empty() && line.rfind("# campaign ", 0) == 0) c.provenance = exportProvenance(line);
        if (line.empty() || line[0] == '#') continue;
        auto f = splitCsv(line);
        if (!header) {
            for (size_t i = 0; i < f.size(); ++i) c.col[f[i]] = i;
            header = true;
        } else {
            c.rows.push_back(std::move(f));
        }
    }
    return c;
}

// Column of each input; mu_d may come as delta_mu (mu_d = mu_s + delta_mu).
std::array<size_t, kInputs> inputColumns(const Csv& c, const std::filesystem::path& csv, bool& deltaMu) {
    deltaMu = !c.col.count("mu_d") && c.col.count("delta_mu");
    std::array<size_t, kInputs> ix{};
    for (size_t k = 0; k < kInputs; ++k) {
        const std::string name = std::string(kInputSpecs[k].name) == "mu_d" && deltaMu ? "delta_mu" : kInputSpecs[k].name;
        if (!c.col.count(name))
            throw InputError(csv.string() + ": no column '" + name +
                             "' (needs mu_s, mu_d or delta_mu, i0, d, rho, feed_kg_h, rpm)");
        ix[k] = c.col.at(name);
    }
    return ix;
}

}  // namespace

Table readTable(const std::filesystem::path& csv) {
    const Csv c = parseCsv(csv);
    bool deltaMu = false;
    const auto ix = inputColumns(c, csv, deltaMu);
    if (!c.col.count(kOutputName)) throw InputError(csv.string() + ": no column '" + kOutputName + "'");
    const size_t mcol = c.col.at(kOutputName);
    Table t;
    t.provenance = c.provenance;
    size_t rowNo = 0;
    for (const auto& f : c.rows) {
        ++rowNo;
        const auto field = [&](const char* name) -> std::string {
            return c.col.count(name) && c.col.at(name) < f.size() ? f[c.col.at(name)] : std::string();
        };
        if ((!field("status").empty() && field("status") != "done") || field("steady") == "false" ||
            field("steady") == "0") {
            ++t.skipped;
            continue;
        }
        // A campaign export's replicate (a design point run again from another deposit, the only rows
        // with a deposit of their own) would count its point twice, as in a campaign's table.
        const bool replicate = !field("initial_loading_kg").empty();
        Row r;
        r.id = !field("scene_hash").empty() ? field("scene_hash")
               : !field("index").empty()    ? field("index")
                                            : std::to_string(rowNo);
        try {
            for (size_t k = 0; k < kInputs; ++k) r.x[k] = std::stod(f.at(ix[k]));
            r.m = std::stod(f.at(mcol));
        } catch (const std::exception&) {
            ++t.skipped;
            continue;
        }
        if (deltaMu) r.x[kMuD] += r.x[kMuS];
        const std::string start = field("start");
        if (replicate) r.depositKg = numberOr(field("initial_loading_kg"), -1);
        else if (start.rfind("deposit:", 0) == 0) r.depositKg = numberOr(start.substr(8), -1);
        if (replicate) {
            ++t.replicates;
            t.replicateRuns.push_back(r);
        } else {
            t.rows.push_back(r);
        }
    }
    return t;
}

TwoStates twoStatesFromString(const std::string& s) {
    if (s == "protocol") return TwoStates::Protocol;
    if (s == "drop") return TwoStates::Drop;
    if (s == "keep") return TwoStates::Keep;
    throw InputError("two-states", s, "protocol | drop | keep");
}

nlohmann::json resolveTwoStates(Table& t, TwoStates policy, double protocolDepositKg) {
    nlohmann::json report = nlohmann::json::array();
    std::vector<Row> kept;
    for (auto& row : t.rows) {
        std::vector<const Row*> runs{&row};
        for (const auto& rep : t.replicateRuns)
            if (rep.x == row.x) runs.push_back(&rep);
        double lo = row.m, hi = row.m;
        for (const auto* r : runs) lo = std::min(lo, r->m), hi = std::max(hi, r->m);
        if (runs.size() < 2 || !(lo > 0) || hi / lo <= kTwoStateRatio) {
            kept.push_back(row);
            continue;
        }
        // Nearest the protocol's deposit; a warm or unrecorded start is never the protocol's.
        const Row* best = nullptr;
        for (const auto* r : runs)
            if (r->depositKg >= 0 && (!best || std::abs(r->depositKg - protocolDepositKg) < std::abs(best->depositKg - protocolDepositKg)))
                best = r;
        nlohmann::json loadings = nlohmann::json::array(), deposits = nlohmann::json::array();
        for (const auto* r : runs) {
            loadings.push_back(r->m);
            deposits.push_back(r->depositKg >= 0 ? nlohmann::json(r->depositKg) : nlohmann::json());
        }
        nlohmann::json e{{"id", row.id}, {"rpm", row.x[kRpm]}, {"feed_kg_h", row.x[kFeed]}, {"loadings_kg", loadings},
                         {"deposits_kg", deposits}};
        Row label = row;
        bool use = true;
        if (policy == TwoStates::Drop || (policy == TwoStates::Protocol && !best)) use = false;
        else if (policy == TwoStates::Protocol) label.m = best->m, label.depositKg = best->depositKg;
        e["kept_kg"] = use ? nlohmann::json(label.m) : nlohmann::json();
        report.push_back(e);
        if (use) kept.push_back(label);
    }
    t.rows = std::move(kept);
    return report;
}

std::vector<Point> readInputs(const std::filesystem::path& csv) {
    const Csv c = parseCsv(csv);
    bool deltaMu = false;
    const auto ix = inputColumns(c, csv, deltaMu);
    std::vector<Point> out;
    for (size_t r = 0; r < c.rows.size(); ++r) {
        Point x{};
        for (size_t k = 0; k < kInputs; ++k) {
            try {
                x[k] = std::stod(c.rows[r].at(ix[k]));
            } catch (const std::exception&) {
                throw InputError(csv.string() + ": row " + std::to_string(r + 1) + ": " + kInputSpecs[k].name +
                                 " is not a number");
            }
        }
        if (deltaMu) x[kMuD] += x[kMuS];
        out.push_back(x);
    }
    return out;
}

void requirePhysical(const Point& x) {
    requireRange("mu-s", x[kMuS], 0.0, 10.0);
    if (!(x[kMuD] > x[kMuS]))
        throw InputError("mu-d", formatNumber(x[kMuD]), "greater than mu-s = " + formatNumber(x[kMuS]));
    requireRange("mu-d", x[kMuD], 0.0, 10.0);
    requirePositive("i0", x[kI0]);
    requirePositive("d", x[kD]);
    requirePositive("rho", x[kRho]);
    requirePositive("feed-kg-h", x[kFeed]);
    requirePositive("rpm", x[kRpm]);
}

}  // namespace mixload::surrogates
