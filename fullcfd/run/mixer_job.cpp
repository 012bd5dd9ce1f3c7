// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/mixer_job.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <regex>
#include <sstream>

#include "cases/meshed_geometry.hpp"
#include "cases/mixer3d.hpp"
#include "common/atomic_file.hpp"
#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "common/process.hpp"
#include "post/mesh_geometry.hpp"
#include "post/mixer_results.hpp"
#include "post/run_profile.hpp"
#include "run/foam_runner.hpp"
#include "run/label_protocol.hpp"
#include "run/monitor_state.hpp"
#include "run/run_dir.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::run {

namespace fs = std::filesystem;

namespace {
bool isFieldFile(const fs::path& source) { return source.extension() == ".h5"; }

post::FoamMesh readCaseMesh(const fs::path& caseDir) { return post::readPolyMesh(caseDir / "constant" / "polyMesh"); }

double meshVolume(const post::FoamMesh& mesh) {
    const auto v = post::meshGeometry(mesh).cellVolumes;
    return std::accumulate(v.begin(), v.end(), 0.0);
}

constexpr const char* kContinued = "continued at the source's time";

// A sliding-mesh run mapped onto a new case loses the paddles' overlap: measured +1.8% powder after
// 48.6 deg of turn (docs/sliding-mesh.md). So a source of the same mesh turning at the same speed is
// continued instead: its latest time directory (fields, fluxes, turned points) is copied whole and
// the solver restarts at the source's time and angle. Only the inlet's flow rate is this case's;
// for its first step the inlet flux is the source's, and the loading monitor counts what that step
// brings in. The monitor's sums and steady samples start afresh, as they belong to the source's feed.
bool continuesSource(const scene::MixerScene& s, const fs::path& caseDir, const fs::path& src,
                     const nlohmann::json& sourceScene) {
    if (s.method != "sm" || sourceScene.value("method", "") != "sm" || sourceScene.value("rpm", -1.0) != s.rpm ||
        !fs::exists(src / "mesh.json"))
        return false;
    const auto a = nlohmann::json::parse(readFile(src / "mesh.json"));
    const auto b = nlohmann::json::parse(readFile(caseDir / "mesh.json"));
    for (const char* key : {"cells", "total_volume_m3", "patch_faces"})
        if (a.value(key, nlohmann::json()) != b.value(key, nlohmann::json())) return false;
    return true;
}

void continueSource(const fs::path& caseDir, const fs::path& src) {
    const fs::path from = latestTimeDir(src);
    if (from.empty()) throw RunError("no time directory in " + src.string());
    const fs::path to = caseDir / from.filename();
    fs::copy(from, to, fs::copy_options::recursive);
    fs::remove_all(to / "uniform" / "functionObjects");
    const std::regex rate("volumetricFlowRate +constant +[-+0-9.eE]+;");
    const std::string own = readFile(caseDir / "0" / "U");
    std::string u = readFile(to / "U");
    std::smatch ownRate, sourceRate;
    if (!std::regex_search(own, ownRate, rate) || !std::regex_search(u, sourceRate, rate))
        throw RunError("no inlet flow rate in " + (to / "U").string() + " or in this case's 0/U");
    u.replace(sourceRate.position(0), sourceRate.length(0), ownRate.str(0));
    writeFileAtomic(to / "U", u);
}

// Replaces the deposit in <case>/0 by the source run's latest fields; cell-volume weights keep the
// powder volume on a different mesh and copy it exactly on the same one. Between the same kind of
// mesh, mapFieldsPar -consistent maps the patches' values too. From MRF to the sliding mesh (or
// back) the patches differ (the AMI pairs, the caps cut at the rotor's rim: v1912's patch AMI
// aborts on them), so only the cells are mapped and the new case keeps its own boundary values.
nlohmann::json warmStartFromRun(const scene::MixerScene& s, const fs::path& caseDir, const fs::path& source) {
    const fs::path src = fs::absolute(source);
    const double t = warmSourceTime(src);
    const auto sourceScene = nlohmann::json::parse(readFile(src / "scene.json"));
    const bool sourceSm = sourceScene.contains("scene") && sourceScene["scene"].value("method", "mrf") == "sm";
    nlohmann::json start{{"warm_from", src.string()}, {"source_time_s", t},
                         {"source_scene_hash", sourceScene.value("hash", "")}};
    if (fs::exists(src / "result.json"))
        start["source_loading_kg"] =
            nlohmann::json::parse(readFile(src / "result.json")).value("loading_kg", 0.0);
    if (sourceScene.contains("scene") && continuesSource(s, caseDir, src, sourceScene["scene"])) {
        continueSource(caseDir, src);
        start["mapped"] = kContinued;
        return start;
    }
    const bool cellsOnly = sourceSm != (s.method == "sm");
    std::vector<std::string> args{"mapFieldsPar", src.string(), "-sourceTime", "latestTime", "-mapMethod",
                                  "cellVolumeWeight"};
    if (cellsOnly)
        writeFileAtomic(caseDir / "system" / "mapFieldsDict",
                        "FoamFile { version 2.0; format ascii; class dictionary; object mapFieldsDict; }\n"
                        "patchMap ( );\ncuttingPatches ( );\n");
    else
        args.push_back("-consistent");
    runUtility(caseDir, args);
    start["mapped"] = cellsOnly ? "cells" : "cells and patches";
    return start;
}

// Where a run's own time begins: the source's time for a run that continues another, else 0.
double ownTimeOrigin(const fs::path& dir) {
    if (!fs::exists(dir / "start.json")) return 0;
    const auto start = nlohmann::json::parse(readFile(dir / "start.json"));
    return start.value("mapped", "") == kContinued ? start.value("source_time_s", 0.0) : 0.0;
}

// The powder fraction of a field file (its last time: e.g. the field `mixload rom regression --at
// ... --fields` predicts, or a campaign run's kept final fields) as the initial alpha, with the
// file's velocity when it holds one (kept fields do), else at rest. There is no mapping: the file
// must hold this case's mesh (the same cells and volume), which the mesh check's numbers verify.
nlohmann::json warmStartFromField(const scene::MixerScene& s, const fs::path& caseDir, const fs::path& source) {
    const store::SnapshotFile f(source);
    const Eigen::VectorXd alpha = f.column("alpha", f.times().size() - 1);
    const auto mesh = nlohmann::json::parse(readFile(caseDir / "mesh.json"));
    const long cells = mesh.value("cells", 0L);
    const double volume = mesh.value("total_volume_m3", 0.0), fileVolume = f.cellVolumes().sum();
    if (static_cast<long>(alpha.size()) != cells || std::abs(fileVolume - volume) > 1e-6 * volume)
        throw InputError("warm-from", source.string(),
                         "a field file of this run's mesh (" + std::to_string(cells) + " cells, " +
                             std::to_string(volume) + " m3); it holds " + std::to_string(alpha.size()) +
                             " cells, " + std::to_string(fileVolume) + " m3");
    std::ostringstream values;
    values.precision(12);
    values << "internalField nonuniform List<scalar>\n" << alpha.size() << "\n(\n";
    for (double a : alpha) values << std::clamp(a, 0.0, 1.0) << '\n';
    values << ");";
    const auto replaceInternal = [&](const fs::path& file, const std::string& uniform, const std::string& with) {
        std::string text = readFile(file);
        text.replace(text.find(uniform), uniform.size(), with);
        writeFileAtomic(file, text);
    };
    replaceInternal(caseDir / "0" / "alpha.powder", "internalField uniform 0;", values.str());
    const auto fields = f.fields();
    bool withU = false;
    if (std::find(fields.begin(), fields.end(), store::storedFieldName("U")) != fields.end()) {
        const Eigen::VectorXd U = f.column("U", f.times().size() - 1);
        withU = U.size() == 3 * alpha.size() && U.allFinite();
        if (withU) {
            std::ostringstream u;
            u.precision(9);
            u << "internalField nonuniform List<vector>\n" << alpha.size() << "\n(\n";
            for (Eigen::Index c = 0; c < alpha.size(); ++c)
                u << '(' << U[3 * c] << ' ' << U[3 * c + 1] << ' ' << U[3 * c + 2] << ")\n";
            u << ");";
            replaceInternal(caseDir / "0" / "U", "internalField uniform (0 0 0);", u.str());
        }
    }
    nlohmann::json start{{"warm_from", fs::absolute(source).string()},
            {"source_time_s", f.times().back()},
            {"velocity", withU},
            {"field_loading_kg", s.bulkDensity() * alpha.cwiseMax(0.0).cwiseMin(1.0).dot(f.cellVolumes())}};
    // A campaign point's own progress, kept when its run directory was lost (experiments/campaign/
    // progress): the run continues that one, and counts the time it had spent (RunSlices reads them).
    const auto prov = f.provenance();
    if (prov.contains("continues_run_dir")) {
        start["continues_run_dir"] = prov["continues_run_dir"];
        if (prov.contains("first_start")) start["first_start"] = nlohmann::json::parse(prov["first_start"].get<std::string>());
        writeFileAtomic(caseDir / "slices.json", prov.value("slices", std::string("[]")));
        if (prov.contains("flow_before_s")) start["flow_before_s"] = std::stod(prov["flow_before_s"].get<std::string>());
        if (prov.contains("monitor"))
            start["monitor_history_s"] = seedMonitorState(caseDir, nlohmann::json::parse(prov["monitor"].get<std::string>()));
    }
    return start;
}
}  // namespace

double warmSourceTime(const fs::path& source) {
    const fs::path src = fs::absolute(source);
    if (isFieldFile(src)) {
        if (!fs::is_regular_file(src)) throw InputError("warm-from", source.string(), "an existing .h5 field file");
        try {
            const store::SnapshotFile f(src);
            const auto fields = f.fields();
            if (std::find(fields.begin(), fields.end(), store::storedFieldName("alpha")) == fields.end() ||
                f.times().empty())
                throw InputError("warm-from", source.string(), "a field file with a stored alpha");
            return f.times().back();
        } catch (const InputError&) {
            throw;
        } catch (const std::exception& e) {
            throw InputError("warm-from", source.string(), std::string("a readable field file (") + e.what() + ")");
        }
    }
    const double t = latestTime(src);
    if (!fs::exists(src / "system" / "controlDict") || !fs::exists(src / "scene.json") || t <= 0)
        throw InputError("warm-from", source.string(),
                         "a mixer run directory with a written time after 0, or a .h5 field file of its mesh");
    return t;
}

nlohmann::json buildMixerMesh(const scene::MixerScene& s, const fs::path& caseDir, int np) {
    cases::writeMixerMeshCase(s, caseDir, np);
    // The O-grid's blocks hold the whole barrel but the shaft: what subsetMesh removes from them is
    // the impeller as meshed, measured here beside the boxes' volume.
    double blocksVolume = 0;
    for (const auto& step : cases::mixerMeshSteps(s)) {
        runUtility(caseDir, step);
        if (s.mesher == "ogrid" && step.front() == "blockMesh") blocksVolume = meshVolume(readCaseMesh(caseDir));
    }
    auto mesh = post::readCheckMesh(caseDir);
    const auto polyMesh = readCaseMesh(caseDir);
    mesh["checksum"] = post::meshChecksum(polyMesh);
    mesh["geometry"] = cases::meshedGeometry(s).toJson();
    if (blocksVolume > 0) mesh["geometry"]["paddle_volume_cut_m3"] = blocksVolume - meshVolume(polyMesh);
    writeFileAtomic(caseDir / "mesh.json", mesh.dump(2));
    if (mesh.value("failed_checks", 0) > 0 && !mesh.value("ok", false))
        throw RunError("checkMesh failed " + std::to_string(mesh.value("failed_checks", 0)) + " checks; see " +
                       (caseDir / "log.checkMesh").string());
    for (const char* patch : {"inlet", "outlet"})
        if (mesh.contains("patch_faces") && mesh["patch_faces"].value(patch, 1L) == 0)
            throw RunError(std::string("the mesh has no face on the ") + patch + " patch (cell size " +
                           formatNumber(s.cellSize) + " m is too coarse to resolve it): use a finer mesh");
    return mesh;
}

fs::path defaultMixerDir(const scene::MixerScene& s, int np) {
    return fs::path("runs") / ("mixer-" + s.hash() + (np > 1 ? "-np" + std::to_string(np) : ""));
}

nlohmann::json runMixer(const MixerJob& job) {
    const auto& s = job.scene;
    s.validate();
    cases::requireSceneGeometry(s);
    requireRange("np", job.np, 1, 256);
    // The sliding mesh's fragment transport (fullcfd/solver/fragmentAMI.H) keeps its fragments
    // on one process.
    if (s.method == "sm" && job.np > 1)
        throw InputError("np", std::to_string(job.np), "1 with --method sm (the sliding mesh runs serially)");
    if (!job.warmFrom.empty()) warmSourceTime(job.warmFrom);
    const fs::path dir = fs::absolute(job.out.empty() ? defaultMixerDir(s, job.np) : job.out);
    const RunDirLock lock(dir);
    if (auto done = checkRunDir(dir, s.hash(), job.reuse)) {
        if (job.snapshots) addSnapshots(*done, dir);
        return *done;
    }
    // Checked here, after the finished result is read and before the case is built: a driver whose
    // time is up still reports what finished and spends nothing on a mesh it will not run.
    if (timeIsUp(job.deadline)) throw NotStarted("mixer run not started: its time was up");
    const auto t0 = std::chrono::steady_clock::now();
    double meshSeconds = 0;
    const bool fresh = !job.reuse || !fs::exists(dir / "constant" / "polyMesh");
    if (fresh) {
        buildCaseAtomically(dir, [&](const fs::path& tmp) {
            writeFileAtomic(tmp / "scene.json",
                            nlohmann::json{{"hash", s.hash()}, {"scene", s.toJson()}}.dump(2));
            buildMixerMesh(s, tmp, job.np);
            cases::writeMixerSolverCase(s, tmp);
            if (!job.warmFrom.empty() && isFieldFile(job.warmFrom)) {
                writeFileAtomic(tmp / "start.json", warmStartFromField(s, tmp, job.warmFrom).dump(2));
            } else if (!job.warmFrom.empty()) {
                // No deposit first: cells the source's mesh does not cover (the sliding mesh keeps
                // 26 cells on 2 cm that MRF's mesh cuts away) start as air, not as part of a bed.
                writeFileAtomic(tmp / "start.json", warmStartFromRun(s, tmp, job.warmFrom).dump(2));
                if (const double t = ownTimeOrigin(tmp); t > 0) cases::writeMixerControlDict(s, tmp, false, false, t);
            } else {
                runUtility(tmp, {"setFields"});
            }
        });
        meshSeconds = secondsSince(t0);
    }

    const double origin = ownTimeOrigin(dir);
    if (job.snapshots || job.profile) cases::writeMixerControlDict(s, dir, job.snapshots, job.profile, origin);
    SolverRun r;
    r.caseDir = dir;
    r.np = job.np;
    r.endTime = s.method == "lts" ? s.ltsIterations : origin + s.endTime;
    r.progress = job.progress;
    r.deadline = job.deadline;
    r.label = "mixer " + s.method;
    const auto cost = runSolverCounted(r, t0, meshSeconds);

    nlohmann::json result = post::mixerResult(s, dir);
    const auto mesh = nlohmann::json::parse(readFile(dir / "mesh.json"));
    result["cells"] = mesh.value("cells", 0L);
    result["mesh"] = mesh;
    recordRunCost(result, cost, t0, job.np, !fresh);
    result["start"] = fs::exists(dir / "start.json")
                          ? nlohmann::json::parse(readFile(dir / "start.json"))
                          : nlohmann::json{{"deposit_kg", s.initialLoadingKg}};
    // setFields fills whole cells, those whose centre lies under the deposit's surface: a layer
    // thinner than a cell is laid short (measured: 0.0235 kg of 0.06 kg asked on 2 cm). The start
    // that was run is the one recorded, and a start far from the one asked is said.
    if (result["start"].contains("deposit_kg") && result.contains("initial_loading_kg")) {
        const double asked = result["start"]["deposit_kg"].get<double>(), laid = result["initial_loading_kg"].get<double>();
        result["start"]["laid_kg"] = laid;
        if (laidFarFromAsked(asked, laid)) {
            std::ostringstream w;
            w << "the deposit laid holds " << laid << " kg of the " << asked
              << " kg asked: the mesh cannot resolve a layer that thin or thick, so the run started elsewhere than asked";
            post::addWarning(result, w.str());
        }
    }
    judgeLabel(s, dir, result);
    if (job.profile) result["profile"] = post::readRunProfile(dir);
    finishRun(result, dir, s.hash(), dir / "loading.png", post::plotLoading(s, dir), job.snapshots);
    return result;
}

}  // namespace mixload::run
