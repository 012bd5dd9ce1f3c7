// SPDX-License-Identifier: GPL-3.0-or-later
// Replays a finished mixer run's loading history through both steady tests, sampled as the
// loading monitor samples it, to compare where each would have stopped the run and with which
// loading: the evidence for the balance verdict's false-steady rate (README, "Cost of a steady
// point").
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mixload::post {

// The long-time mean of a loading history that does not settle (a deep bed that surges over the
// weir: docs/paper-claims.md): from `from` to the end, cut into `batches` equal batches, the
// time-weighted mean of each, their mean and the Student-t 95% half-width of it. Batches shorter
// than the signal's correlation time make the interval optimistic; a residence time or more each
// is the intended use.
struct BatchMeans {
    double from = 0, batchLength = 0, mean = 0, halfWidth95 = 0;
    std::vector<double> means;
};
BatchMeans batchMeans(const std::vector<double>& t, const std::vector<double>& M, double from, int batches);

// For the run in caseDir (its scene.json gives rpm, feed and windows): the history's end and final
// loading (mean of its last window), and for "windows" and "balance" the first time each test
// passes with its loading, or null. tol and flowTol: the tests' tolerances; residence: the window
// test's share of the residence time M/feed (0.5 as runs use it).
// batches >= 2 adds "long_time" (batchMeans from `from`; from < 0: the window test's verdict, or
// half the history when it has none).
nlohmann::json replayVerdicts(const std::filesystem::path& caseDir, double tol, double flowTol,
                              double residence = 0.5, int batches = 0, double from = -1);

// Replays every run and adds, per test, the verdict's error against the final loading, and the
// counts: balance verdicts, false steadies (error above tol), balance verdicts earlier than the
// window test's.
nlohmann::json replayAll(const std::vector<std::string>& runDirs, double tol, double flowTol,
                         double residence, int batches = 0, double from = -1);

}  // namespace mixload::post
