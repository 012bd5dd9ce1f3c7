// SPDX-License-Identifier: GPL-3.0-or-later
#include "post/level_history.hpp"

#include <algorithm>
#include <cmath>

#include "steadyLoading.H"

namespace mixload::post {

LevelHistory levelHistory(const std::vector<double>& t, const std::vector<double>& M, double feedKgS,
                          double finalWindow, double smoothing, double band) {
    LevelHistory h;
    h.band = band;
    h.smoothing = smoothing;
    if (t.size() < 3 || feedKgS <= 0) return h;
    const double t0 = t.front(), end = t.back();
    const double W = std::clamp(finalWindow, 0.0, end - t0);
    h.finalLevel = W > 0 ? steady::windowMean(t, M, end - W, end) : M.back();
    h.residenceTime = std::abs(h.finalLevel) / feedKgS;
    const double span = std::clamp(smoothing, 0.0, end - t0);
    const double tol = band * std::max(std::abs(h.finalLevel), 1e-12);
    // The trailing mean at every sample from one span after the start; the band is tested on it.
    bool entered = false;
    double outsideSince = -1;  // start of the current stretch outside the band, once entered
    h.settledAt = t0;
    for (size_t i = 0; i < t.size(); ++i) {
        if (t[i] < t0 + span) continue;
        const double m = span > 0 ? steady::windowMean(t, M, t[i] - span, t[i]) : M[i];
        const bool inside = std::abs(m - h.finalLevel) <= tol;
        if (!inside) {
            h.settledAt = t[i];
            if (entered && outsideSince < 0) outsideSince = t[i];
            // Out of the band for a whole span after having been in it: the loading left the level
            // it ends at, not a paddle's passing.
            if (entered && t[i] - outsideSince >= span) h.levelChangeSeen = true;
        } else {
            entered = true;
            outsideSince = -1;
        }
    }
    h.settledResidenceTimes = h.residenceTime > 0 ? (end - h.settledAt) / h.residenceTime : 0;
    return h;
}

}  // namespace mixload::post
