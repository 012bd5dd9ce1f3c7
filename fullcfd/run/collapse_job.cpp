// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/collapse_job.hpp"

#include <chrono>

#include "cases/collapse2d.hpp"
#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "mixload_version.hpp"
#include "post/collapse_results.hpp"
#include "run/foam_runner.hpp"

namespace mixload::run {

namespace fs = std::filesystem;

fs::path defaultCollapseDir(const scene::CollapseScene& s, int np) {
    return fs::path("runs") / ("collapse-" + s.hash() + (np > 1 ? "-np" + std::to_string(np) : ""));
}

nlohmann::json runCollapse(const CollapseJob& job) {
    const auto& s = job.scene;
    s.validate();
    requireRange("np", job.np, 1, 256);
    const fs::path dir = fs::absolute(job.out.empty() ? defaultCollapseDir(s, job.np) : job.out);
    const fs::path sceneFile = dir / "scene.json";

    if (fs::exists(dir)) {
        if (!fs::exists(sceneFile) ||
            nlohmann::json::parse(readFile(sceneFile)).value("hash", "") != s.hash())
            throw InputError("out", dir.string(),
                             "a new directory or a run directory of the same scene");
        if (job.reuse && fs::exists(dir / "result.json")) {
            auto r = nlohmann::json::parse(readFile(dir / "result.json"));
            r["reused"] = true;
            return r;
        }
    }

    const auto t0 = std::chrono::steady_clock::now();
    // --rerun starts over; otherwise a case that has a mesh resumes from its latest time.
    const bool fresh = !job.reuse || !fs::exists(dir / "constant" / "polyMesh");
    if (fresh) {
        // Build the case in a sibling temp dir and rename it into place: a directory under the
        // final name always holds a complete case.
        fs::path tmp = dir;
        tmp += ".tmp";
        fs::remove_all(tmp);
        fs::create_directories(tmp);
        try {
            cases::writeCollapseCase(s, tmp, job.np);
            writeFileAtomic(tmp / "scene.json",
                            nlohmann::json{{"hash", s.hash()}, {"scene", s.toJson()}}.dump(2));
            runUtility(tmp, {"blockMesh"});
        } catch (...) {
            fs::remove_all(tmp);
            throw;
        }
        fs::remove_all(dir);
        fs::rename(tmp, dir);
    }

    SolverRun r;
    r.caseDir = dir;
    r.np = job.np;
    r.endTime = s.capTstar * s.tStar();
    r.progress = job.progress;
    r.label = "collapse a=" + formatNumber(s.aspect);
    const double solverWall = runSolver(r);

    nlohmann::json result = post::collapseResult(s, dir);
    result["wall_seconds"] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    result["solver_wall_seconds"] = solverWall;
    result["np"] = job.np;
    result["resumed"] = !fresh;
    result["run_dir"] = dir.string();
    result["scene_hash"] = s.hash();
    result["mixload_version"] = kVersion;
    result["git_commit"] = kGitCommit;
    result["openfoam_version"] = MIXLOAD_OPENFOAM_VERSION;
    const std::string warn = post::plotCollapse(s, dir);
    result["plot"] = warn.empty() ? (dir / "collapse.png").string() : "";
    if (!warn.empty()) result["plot_warning"] = warn;
    writeFileAtomic(dir / "result.json", result.dump(2));
    return result;
}

}  // namespace mixload::run
