// SPDX-License-Identifier: GPL-3.0-or-later
// What a campaign changes in a point's scene before its second (and last) attempt.
#pragma once
#include "scene/collapse_scene.hpp"
#include "scene/mixer_scene.hpp"

namespace mixload::experiments {

// Half the Courant limit the first attempt ran with, the usual cure for a diverged run. A mixer is
// also run with every cell counted in that limit: exempting air cells let gcm250-v2 diverge on a
// 2 cm mesh, and counting them cured it (docs/mixer.md, "A diverged solution stops the run").
scene::MixerScene retryScene(scene::MixerScene s);
scene::CollapseScene retryScene(scene::CollapseScene s);

}  // namespace mixload::experiments
