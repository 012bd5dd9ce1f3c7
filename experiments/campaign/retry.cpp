// SPDX-License-Identifier: GPL-3.0-or-later
#include "campaign/retry.hpp"

#include <algorithm>
#include <memory>

#include "campaign/driver_lock.hpp"
#include "common/input_error.hpp"

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

nlohmann::json requeuePoint(const CampaignPlace& place, int index) {
    std::unique_ptr<store::Ledger> ledger;
    const auto info = openCampaign(place, ledger);
    const DriverLock lock(place.home(), "campaign requeue");
    const auto runs = ledger->runs(place.name);
    const auto r = std::find_if(runs.begin(), runs.end(), [&](const auto& x) { return x.index == index; });
    if (r == runs.end())
        throw InputError("point", std::to_string(index), "0-" + std::to_string(static_cast<int>(runs.size()) - 1));
    if (r->status == "done")
        throw InputError("point", std::to_string(index), "a point not done (it is done: its result stands)");
    nlohmann::json before{{"status", r->status}, {"attempts", r->attempts}, {"error", r->error}};
    ledger->requeueAsFirst(r->id);
    return {{"campaign", info.name}, {"index", index}, {"before", before}, {"status", "queued"}, {"attempts", 0}};
}

}  // namespace mixload::experiments
