// SPDX-License-Identifier: GPL-3.0-or-later
#include "campaign/rebase.hpp"

#include <filesystem>

#include "campaign/driver_lock.hpp"
#include "cases/meshed_geometry.hpp"
#include "common/atomic_file.hpp"
#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "mixload_version.hpp"
#include "run/mixer_job.hpp"
#include "store/ledger.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {

// The checksum of a scene's mesh, meshed in dir (removed afterwards).
std::string meshChecksumOf(const scene::MixerScene& s, const fs::path& dir) {
    fs::remove_all(dir);
    fs::create_directories(dir);
    const auto mesh = run::buildMixerMesh(s, dir);
    fs::remove_all(dir);
    return mesh.value("checksum", std::string());
}

nlohmann::json withoutGeometry(nlohmann::json j) {
    j.erase("name");
    j.erase("geometry");
    return j;
}

}  // namespace

nlohmann::json rebaseCampaign(const CampaignPlace& o, const std::string& sceneName) {
    const DriverLock lock(o.home(), "campaign rebase");
    std::unique_ptr<store::Ledger> ledger;
    const auto c = openCampaign(o, ledger);
    if (c.scene != "mixer") throw InputError("campaign", o.name, "a mixer campaign (this one is a " + c.scene + " campaign)");
    nlohmann::json base = c.sceneJson;
    const std::string oldName = base.value("scene", std::string());
    base["scene"] = sceneName;
    const auto before = mixerSceneFor(c.sceneJson, nlohmann::json::object());
    const auto after = mixerSceneFor(base, nlohmann::json::object());
    cases::requireSceneGeometry(after);
    const auto a = withoutGeometry(before.toJson()), b = withoutGeometry(after.toJson());
    std::string differ;
    for (const auto& [k, v] : b.items())
        if (!a.contains(k) || a[k] != v) differ += (differ.empty() ? "" : ", ") + k;
    for (const auto& [k, v] : a.items())
        if (!b.contains(k)) differ += (differ.empty() ? "" : ", ") + k;
    if (!differ.empty())
        throw InputError("scene", sceneName, "a revision of " + oldName + " that restates only its geometry (" + after.name +
                                                 " differs from it in " + differ + ")");
    const fs::path scratch = o.home() / ".rebase-mesh";
    const std::string was = meshChecksumOf(before, scratch / "before"), is = meshChecksumOf(after, scratch / "after");
    fs::remove_all(scratch);
    if (was.empty() || was != is)
        throw InputError("scene", sceneName,
                         "a scene whose " + before.meshLabel() + " mesh is cell for cell " + oldName + "'s (checksum " + was +
                             "; " + after.name + "'s is " + is + ")");
    base["rebased"] = {{"from_scene", oldName}, {"from_scene_hash", c.sceneHash}, {"mesh_checksum", is},
                       {"date", utcNow()}, {"mixload_version", kVersion}, {"git_commit", kGitCommit}};

    // Unfinished points resume in their directories, renamed to the new hash: a rename of each
    // whole directory, so a crash here leaves every run directory whole under one name or the other
    // (a later `campaign run` finds the renamed ones; one left under the old name starts afresh).
    std::vector<std::pair<long, nlohmann::json>> params;
    nlohmann::json moved = nlohmann::json::array();
    for (const auto& r : ledger->runs(o.name)) {
        nlohmann::json p = r.params;
        const std::string oldHash = p.value("scene_hash", std::string());
        p.erase("scene_hash");
        const auto s = mixerSceneFor(base, p);
        p["scene_hash"] = s.hash();
        if (r.status == "done") {
            p["scene_hash_before_rebase"] = oldHash;
        } else {
            const fs::path from = o.home() / "runs" / (std::to_string(r.index) + "-" + oldHash);
            const fs::path to = o.home() / "runs" / (std::to_string(r.index) + "-" + s.hash());
            if (fs::is_directory(from) && !fs::exists(to)) {
                writeFileAtomic(from / "scene.json", nlohmann::json{{"hash", s.hash()}, {"scene", s.toJson()}}.dump(2));
                // Its mesh, made before meshes recorded their impeller, gets the record it shares.
                if (fs::exists(from / "mesh.json")) {
                    auto mesh = nlohmann::json::parse(readFile(from / "mesh.json"));
                    mesh["checksum"] = is;
                    mesh["geometry"] = cases::meshedGeometry(s).toJson();
                    writeFileAtomic(from / "mesh.json", mesh.dump(2));
                }
                fs::rename(from, to);
                moved.push_back({{"index", r.index}, {"run_dir", to.string()}});
            }
        }
        params.emplace_back(r.id, p);
    }
    ledger->rebaseCampaign(o.name, base, after.hash(), params);
    return {{"campaign", o.name}, {"from_scene", oldName}, {"scene", sceneName}, {"mesh", after.meshLabel()},
            {"mesh_checksum", is}, {"points", params.size()}, {"moved_run_dirs", moved}};
}

}  // namespace mixload::experiments
