// SPDX-License-Identifier: GPL-3.0-or-later
#include "campaign/retry.hpp"

namespace mixload::experiments {

scene::MixerScene retryScene(scene::MixerScene s) {
    // courantLimit(), not maxCourant: the sliding mesh caps the limit at 0.5, and halving the
    // scene's 1 would have left the retry where the first attempt diverged.
    s.maxCourant = 0.5 * s.courantLimit();
    s.numerics.courantAlphaMin = 0;
    return s;
}

scene::CollapseScene retryScene(scene::CollapseScene s) {
    s.maxCourant *= 0.5;
    return s;
}

}  // namespace mixload::experiments
