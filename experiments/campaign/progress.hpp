// SPDX-License-Identifier: GPL-3.0-or-later
// A campaign point stopped at its driver's deadline resumes in its run directory. A machine that
// comes back without the directories (the stores outside the work tree are gone) would lose all it
// ran: a low-feed bed on 1 cm holds hours. So when a driver stops a mixer point at its deadline, the
// point's latest written fields (powder fraction and velocity) and the time counted on it are kept
// in <home>/progress.h5, landed with the ledger; a point whose directory is gone starts from them.
#pragma once
#include <filesystem>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

namespace mixload::experiments {

// Keeps (replacing any earlier entry of the point) the latest written time of the run directory
// `runDir` of design point `index` in <home>/progress.h5, rewritten whole and atomically. Returns
// {index, time_s, core_seconds}, or null when the directory has no written time to keep yet.
nlohmann::json keepPointProgress(const std::filesystem::path& home, int index, const std::filesystem::path& runDir);

// The flow [s] the point had run before a run began, from the run's start record (start.json, or
// `start` in its result) when that run continues the point's kept progress: flow_before_s, or for
// progress kept before that key, the kept time; 0 for a run that began the point.
double flowBefore(const nlohmann::json& start);
double flowBeforeRun(const std::filesystem::path& runDir);

// The flow [s] each point kept in <home>/progress.h5 had run, by design index.
std::map<int, double> keptProgressFlow(const std::filesystem::path& home);

// Drops the entries of points that have their own result now (the file goes when none is left).
void dropFinishedProgress(const std::filesystem::path& home, int index);

// The field file the point starts from when its run directory `runDir` is gone and <home>/progress.h5
// keeps that directory's progress: written once to <home>/warm/progress-<index>.h5, with the kept
// time's slices in its provenance (the new run counts them). Empty otherwise.
std::filesystem::path progressStart(const std::filesystem::path& home, int index, const std::filesystem::path& runDir);

}  // namespace mixload::experiments
