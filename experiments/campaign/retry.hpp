// SPDX-License-Identifier: GPL-3.0-or-later
// What a campaign changes in a point's scene before its second (and last) attempt.
#pragma once
#include <nlohmann/json.hpp>

#include "campaign/campaign.hpp"
#include "scene/collapse_scene.hpp"
#include "scene/mixer_scene.hpp"

namespace mixload::experiments {

// Half the Courant limit the first attempt ran with, the usual cure for a diverged run. A mixer is
// also run with every cell counted in that limit: exempting air cells let gcm250-v2 diverge on a
// 2 cm mesh, and counting them cured it (docs/mixer.md, "A diverged solution stops the run").
scene::MixerScene retryScene(scene::MixerScene s);
scene::CollapseScene retryScene(scene::CollapseScene s);

// Gives a queued or failed point its first attempt back, once the cause of its failure is mended
// (e.g. a resume that failed at once): it then continues in its first attempt's directory, not
// from scratch in the retry's. Takes the driver lock (no driver may run). A done or unknown point
// is an InputError. Returns the point's status, attempts and error before.
nlohmann::json requeuePoint(const CampaignPlace& place, int index);

}  // namespace mixload::experiments
