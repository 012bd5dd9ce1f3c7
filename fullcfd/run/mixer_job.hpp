// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <chrono>
#include <cmath>
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

#include "scene/mixer_scene.hpp"

namespace mixload::run {

struct MixerJob {
    scene::MixerScene scene;
    int np = 1;
    std::filesystem::path out;  // empty: runs/mixer-<hash>[-np<N>]
    bool progress = false;
    bool reuse = true;          // return a finished run's result instead of running again
    bool snapshots = false;     // keep every written time and export <run dir>/snapshots.h5
    bool profile = false;       // record where the steps and the time go (result "profile")
    // Warm start: begin from the latest fields of this run directory (any scene, any mesh: the
    // fields are mapped by cell-volume weights), or from the powder fraction of a .h5 field file
    // of this run's mesh (air at rest), instead of the scene's deposit.
    std::filesystem::path warmFrom;
    // Campaigns stop long runs here; they resume later from their last written time. Past it a run
    // does not start (NotStarted), though a finished one is still returned.
    std::optional<std::chrono::steady_clock::time_point> deadline;
};

// Meshes, runs (or resumes, or reuses) a mixer run and returns its result record, also written to
// <run dir>/result.json. The scene is validated before anything is created.
nlohmann::json runMixer(const MixerJob& job);

// Writes the mesh case of a scene into caseDir and meshes it; returns (and writes to mesh.json)
// checkMesh's figures, the impeller as meshed and the mesh's checksum. RunError when the mesh fails
// its checks or has no inlet or outlet face. It does not check the scene's geometry (runMixer does):
// `campaign rebase` meshes a superseded scene to show that its mesh is the new scene's.
nlohmann::json buildMixerMesh(const scene::MixerScene& s, const std::filesystem::path& caseDir, int np = 1);

// The latest time of a warm start's source; InputError (field warm-from) unless it is a mixer run
// directory with a written time after 0 or a .h5 field file with a stored alpha.
double warmSourceTime(const std::filesystem::path& source);

std::filesystem::path defaultMixerDir(const scene::MixerScene& s, int np);

// Whether the deposit the mesh laid is far enough from the one asked (more than 10%) to be said:
// setFields fills whole cells, so a layer near a cell's height is laid short or long.
inline bool laidFarFromAsked(double askedKg, double laidKg) { return askedKg > 0 && std::abs(laidKg - askedKg) > 0.1 * askedKg; }

}  // namespace mixload::run
