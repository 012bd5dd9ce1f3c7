// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/collapse_job.hpp"

#include <chrono>
#include <cmath>

#include "cases/collapse2d.hpp"
#include "common/atomic_file.hpp"
#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "common/process.hpp"
#include "post/collapse_results.hpp"
#include "run/foam_runner.hpp"
#include "run/run_dir.hpp"

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
    const RunDirLock lock(dir);
    if (auto done = checkRunDir(dir, s.hash(), job.reuse)) {
        if (job.snapshots) addSnapshots(*done, dir);
        return *done;
    }
    // As for the mixer (mixer_job.cpp): a finished run is read, a new one is not begun.
    if (timeIsUp(job.deadline)) throw NotStarted("collapse run not started: its time was up");

    const auto t0 = std::chrono::steady_clock::now();
    // --rerun starts over; otherwise a case that has a mesh resumes from its latest time.
    const bool fresh = !job.reuse || !fs::exists(dir / "constant" / "polyMesh");
    double meshSeconds = 0;  // serial, before the solver holds np cores
    if (fresh) {
        buildCaseAtomically(dir, [&](const fs::path& tmp) {
            cases::writeCollapseCase(s, tmp, job.np);
            writeFileAtomic(tmp / "scene.json",
                            nlohmann::json{{"hash", s.hash()}, {"scene", s.toJson()}}.dump(2));
            runUtility(tmp, {"blockMesh"});
        });
        meshSeconds = secondsSince(t0);
    }

    SolverRun r;
    r.caseDir = dir;
    r.np = job.np;
    r.endTime = s.capTstar * s.tStar();
    r.progress = job.progress;
    r.deadline = job.deadline;
    r.label = "collapse a=" + formatNumber(s.aspect);
    // Every process that works on the run counts its time (a campaign stopped at --max-hours
    // resumes it in another), as for the mixer.
    const auto cost = runSolverCounted(r, t0, meshSeconds);

    nlohmann::json result = post::collapseResult(s, dir);
    // A collapse that lost powder has no runout to report: refuse it rather than write a result
    // that looks complete (the domain is sized to an estimate of the runout; very mobile powders
    // outrun it and leave through the open side).
    const double lost = result["powder_mass_error"].get<double>();
    if (std::abs(lost) > 1e-3 || result["powder_reached_domain_end"].get<bool>())
        throw RunError("collapse a=" + formatNumber(s.aspect) + " of " + s.material.name + ": the powder volume changed by " +
                       formatNumber(100 * lost) + "%" +
                       (result["powder_reached_domain_end"].get<bool>()
                            ? " and the deposit reaches the domain's open right side: the runout is longer than the "
                              "domain sized for it (" + formatNumber((s.domainWidth() - s.length) / s.length) +
                                  " column lengths of runout)"
                            : "") +
                       "; no result written, the fields are in " + dir.string());
    recordRunCost(result, cost, t0, job.np, !fresh);
    finishRun(result, dir, s.hash(), dir / "collapse.png", post::plotCollapse(s, dir), job.snapshots);
    return result;
}

}  // namespace mixload::run
