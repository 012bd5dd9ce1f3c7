// SPDX-License-Identifier: GPL-3.0-or-later
// Training and checking data: one row per finished full run, inputs and the loading M.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "inputs.hpp"

namespace mixload::surrogates {

struct Row {
    std::string id;  // the run's scene hash (stable across ledgers and exports)
    Point x{};
    double m = 0;    // mixer loading [kg]
    double depositKg = -1;  // the powder the run started from, when it started from a deposit (-1: a warm or unrecorded start)
};

struct Table {
    std::vector<Row> rows;
    size_t skipped = 0;  // rows not usable: not done, not steady, or missing a value
    // Campaign runs that repeat a design point from another deposit (campaign replicate): they
    // measure the label noise (campaign noise) and are neither training nor hold-out points.
    size_t replicates = 0;
    std::vector<Row> replicateRuns;  // those runs, for resolveTwoStates
    // From a campaign export's first line ("# campaign NAME, scene ..., design ..., seed ..., base
    // {...}, created ... by mixload V (COMMIT)"): campaign, design, seed, base, campaign_created,
    // campaign_mixload_version, campaign_git_commit, as a model fitted to the campaign records
    // them. Empty for other tables.
    nlohmann::json provenance = nlohmann::json::object();
};

// A point and its replicate whose loadings differ by more than this ratio sit in two steady states
// (the start picked the state), not in one state with label noise: on gcm250-v2 one state's
// replicates differ by 2-7%, v2 point 1 (250 rpm) by 6.8 times (a dense bed kept from 0.32 kg
// against a film from 0.055 kg).
inline constexpr double kTwoStateRatio = 1.5;

// What a point in two states trains and checks with: protocol (the run whose deposit is nearest the
// label protocol's, its start), drop (neither: the point is not a function of its inputs), keep
// (the point's own run, as before issue 64).
enum class TwoStates { Protocol, Drop, Keep };
TwoStates twoStatesFromString(const std::string& s);  // InputError naming --two-states

// Applies the policy to every row with a replicate in another state and returns what it did, one
// entry per such point: {id, rpm, feed_kg_h, loadings_kg, deposits_kg, kept_kg or null}.
nlohmann::json resolveTwoStates(Table& t, TwoStates policy, double protocolDepositKg);

// Reads a CSV such as `mixload campaign export` writes ('#' lines are comments). Needs the seven
// input columns (mu_d, or delta_mu with mu_d = mu_s + delta_mu) and loading_kg; uses scene_hash (or
// index, or the row number) as id; skips rows whose status is not "done" or whose steady is false.
// Throws InputError naming the file and the missing column.
Table readTable(const std::filesystem::path& csv);

// Just the seven inputs of every row (prediction batches). Throws InputError naming the row.
std::vector<Point> readInputs(const std::filesystem::path& csv);

// Throws InputError (field, value, allowed range) for a non-physical point: mu_d <= mu_s,
// non-positive d, rho, i0, feed or rpm, negative mu_s.
void requirePhysical(const Point& x);

}  // namespace mixload::surrogates
