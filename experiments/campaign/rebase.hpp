// SPDX-License-Identifier: GPL-3.0-or-later
// `campaign rebase`: moves a mixer campaign onto a scene revision whose mesh is cell for cell the
// one the campaign ran on (gcm250-v2 -> gcm250-v3 on 1 cm: the same cut paddle, now stated), so
// that it runs on under the new scene without redoing or relabelling what is done.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "campaign/campaign.hpp"

namespace mixload::experiments {

// Refuses (InputError, nothing changed) unless no driver runs, the campaign is a mixer campaign, the
// new scene's paddles can be cut on the campaign's mesh, every input but the geometry is the same,
// and the two scenes' meshes (built here in a scratch directory) have the same checksum. Then, in
// one ledger transaction: the base names the new scene and records the rebase (old scene and hash,
// checksum, date, code); every point's scene hash is the new one (a finished run keeps its old one
// as scene_hash_before_rebase); and each unfinished point's run directory is renamed to the new
// hash with its scene.json rewritten, so that `campaign run` resumes it where it stood.
nlohmann::json rebaseCampaign(const CampaignPlace& place, const std::string& scene);

}  // namespace mixload::experiments
