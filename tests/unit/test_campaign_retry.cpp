// SPDX-License-Identifier: GPL-3.0-or-later
// A campaign's second attempt at a failed point: what it changes, and that it runs apart.
#include <gtest/gtest.h>

#include "campaign/retry.hpp"
#include "scene/mixer_scene.hpp"

using namespace mixload;

TEST(CampaignRetry, HalvesTheLimitTheFirstAttemptRanWith) {
    auto mrf = scene::loadMixerScene("gcm250-v2");
    mrf.numerics.courantAlphaMin = 0.05;
    const auto mrf2 = experiments::retryScene(mrf);
    EXPECT_DOUBLE_EQ(mrf2.courantLimit(), 0.5 * mrf.courantLimit());
    EXPECT_EQ(mrf2.numerics.courantAlphaMin, 0.0);  // every cell counted
    EXPECT_NE(mrf2.hash(), mrf.hash());             // its own run directory, not the failed one's

    // The sliding mesh runs at most at 0.5 whatever maxCourant says: its retry must go below that.
    auto sm = mrf;
    sm.method = "sm";
    ASSERT_DOUBLE_EQ(sm.courantLimit(), scene::kSlidingMeshMaxCourant);
    EXPECT_DOUBLE_EQ(experiments::retryScene(sm).courantLimit(), 0.5 * scene::kSlidingMeshMaxCourant);

    scene::CollapseScene col;
    EXPECT_DOUBLE_EQ(experiments::retryScene(col).maxCourant, 0.5 * col.maxCourant);
}
