// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/mixer_job.hpp"

#include <chrono>

#include "cases/mixer3d.hpp"
#include "common/atomic_file.hpp"
#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "post/mixer_results.hpp"
#include "post/run_profile.hpp"
#include "run/foam_runner.hpp"
#include "run/run_dir.hpp"

namespace mixload::run {

namespace fs = std::filesystem;

namespace {
// Replaces the deposit in <case>/0 by the source run's latest fields. mapFieldsPar keeps the new
// case's boundary conditions (feed, rotation) and maps only values; cell-volume weights keep the
// powder volume on a different mesh and copy it exactly on the same one.
nlohmann::json warmStart(const fs::path& caseDir, const fs::path& source) {
    const fs::path src = fs::absolute(source);
    const double t = warmSourceTime(src);
    runUtility(caseDir, {"mapFieldsPar", src.string(), "-sourceTime", "latestTime", "-consistent",
                         "-mapMethod", "cellVolumeWeight"});
    nlohmann::json start{{"warm_from", src.string()}, {"source_time_s", t}};
    if (fs::exists(src / "scene.json"))
        start["source_scene_hash"] = nlohmann::json::parse(readFile(src / "scene.json")).value("hash", "");
    if (fs::exists(src / "result.json"))
        start["source_loading_kg"] =
            nlohmann::json::parse(readFile(src / "result.json")).value("loading_kg", 0.0);
    writeFileAtomic(caseDir / "start.json", start.dump(2));
    return start;
}
}  // namespace

double warmSourceTime(const fs::path& source) {
    const fs::path src = fs::absolute(source);
    const double t = latestTime(src);
    if (!fs::exists(src / "system" / "controlDict") || !fs::exists(src / "scene.json") || t <= 0)
        throw InputError("warm-from", source.string(),
                         "a mixer run directory with a written time after 0");
    return t;
}

fs::path defaultMixerDir(const scene::MixerScene& s, int np) {
    return fs::path("runs") / ("mixer-" + s.hash() + (np > 1 ? "-np" + std::to_string(np) : ""));
}

nlohmann::json runMixer(const MixerJob& job) {
    const auto& s = job.scene;
    s.validate();
    requireRange("np", job.np, 1, 256);
    if (!job.warmFrom.empty()) warmSourceTime(job.warmFrom);
    const fs::path dir = fs::absolute(job.out.empty() ? defaultMixerDir(s, job.np) : job.out);
    const RunDirLock lock(dir);
    if (auto done = checkRunDir(dir, s.hash(), job.reuse)) {
        if (job.snapshots) addSnapshots(*done, dir);
        return *done;
    }
    const auto t0 = std::chrono::steady_clock::now();
    double meshSeconds = 0;
    const bool fresh = !job.reuse || !fs::exists(dir / "constant" / "polyMesh");
    if (fresh) {
        buildCaseAtomically(dir, [&](const fs::path& tmp) {
            cases::writeMixerMeshCase(s, tmp, job.np);
            writeFileAtomic(tmp / "scene.json",
                            nlohmann::json{{"hash", s.hash()}, {"scene", s.toJson()}}.dump(2));
            for (const auto& step : cases::mixerMeshSteps(s)) runUtility(tmp, step);
            const auto mesh = post::readCheckMesh(tmp);
            writeFileAtomic(tmp / "mesh.json", mesh.dump(2));
            if (mesh.value("failed_checks", 0) > 0 && !mesh.value("ok", false))
                throw RunError("checkMesh failed " + std::to_string(mesh.value("failed_checks", 0)) +
                               " checks; see " + (tmp / "log.checkMesh").string());
            cases::writeMixerSolverCase(s, tmp);
            runUtility(tmp, {"setFields"});
            if (!job.warmFrom.empty()) warmStart(tmp, job.warmFrom);
        });
        meshSeconds = secondsSince(t0);
    }

    if (job.snapshots || job.profile) cases::writeMixerControlDict(s, dir, job.snapshots, job.profile);
    SolverRun r;
    r.caseDir = dir;
    r.np = job.np;
    r.endTime = s.method == "lts" ? s.ltsIterations : s.endTime;
    r.progress = job.progress;
    r.deadline = job.deadline;
    r.label = "mixer " + s.method;
    const double solverWall = runSolver(r);

    nlohmann::json result = post::mixerResult(s, dir);
    const auto mesh = nlohmann::json::parse(readFile(dir / "mesh.json"));
    result["cells"] = mesh.value("cells", 0L);
    result["mesh"] = mesh;
    result["wall_seconds"] = secondsSince(t0);
    result["solver_wall_seconds"] = solverWall;
    // Meshing runs serial; the solver holds np cores.
    result["core_seconds"] = meshSeconds + solverWall * job.np;
    result["np"] = job.np;
    result["resumed"] = !fresh;
    result["start"] = fs::exists(dir / "start.json")
                          ? nlohmann::json::parse(readFile(dir / "start.json"))
                          : nlohmann::json{{"deposit_kg", s.initialLoadingKg}};
    if (job.profile) result["profile"] = post::readRunProfile(dir);
    stampProvenance(result, dir, s.hash());
    const std::string warn = post::plotLoading(s, dir);
    result["plot"] = warn.empty() ? (dir / "loading.png").string() : "";
    if (!warn.empty()) result["plot_warning"] = warn;
    writeFileAtomic(dir / "result.json", result.dump(2));
    if (job.snapshots) addSnapshots(result, dir);
    return result;
}

}  // namespace mixload::run
