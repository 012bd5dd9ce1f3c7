// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/mixer_job.hpp"

#include <chrono>

#include "cases/mixer3d.hpp"
#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "post/mixer_results.hpp"
#include "run/foam_runner.hpp"
#include "run/run_dir.hpp"

namespace mixload::run {

namespace fs = std::filesystem;

namespace {
double since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

fs::path defaultMixerDir(const scene::MixerScene& s, int np) {
    return fs::path("runs") / ("mixer-" + s.hash() + (np > 1 ? "-np" + std::to_string(np) : ""));
}

nlohmann::json runMixer(const MixerJob& job) {
    const auto& s = job.scene;
    s.validate();
    requireRange("np", job.np, 1, 256);
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
        });
        meshSeconds = since(t0);
    }

    if (job.snapshots) cases::writeMixerControlDict(s, dir, true);
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
    result["wall_seconds"] = since(t0);
    result["solver_wall_seconds"] = solverWall;
    // Meshing runs serial; the solver holds np cores.
    result["core_seconds"] = meshSeconds + solverWall * job.np;
    result["np"] = job.np;
    result["resumed"] = !fresh;
    stampProvenance(result, dir, s.hash());
    const std::string warn = post::plotLoading(s, dir);
    result["plot"] = warn.empty() ? (dir / "loading.png").string() : "";
    if (!warn.empty()) result["plot_warning"] = warn;
    writeFileAtomic(dir / "result.json", result.dump(2));
    if (job.snapshots) addSnapshots(result, dir);
    return result;
}

}  // namespace mixload::run
