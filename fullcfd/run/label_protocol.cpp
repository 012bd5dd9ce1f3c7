// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/label_protocol.hpp"

#include <cmath>
#include <sstream>

#include "common/input_error.hpp"
#include "post/level_history.hpp"
#include "post/mixer_results.hpp"

namespace mixload::run {

void applyLabelProtocol(scene::MixerOverrides& m) {
    if (m.initialLoadingKg)
        throw InputError("initial-loading-kg", formatNumber(*m.initialLoadingKg),
                         std::string("no start of its own under --protocol ") + kLabelProtocol + " (it starts from " +
                             formatNumber(kLabelDepositKg) + " kg); use --protocol scene for another start");
    if (m.residence)
        throw InputError("steady-window-residence", formatNumber(*m.residence),
                         std::string("no window of its own under --protocol ") + kLabelProtocol + " (windows of " +
                             formatNumber(kLabelWindowResidence) + " residence time); use --protocol scene");
    m.initialLoadingKg = kLabelDepositKg;
    m.residence = kLabelWindowResidence;
    if (!m.endTime) m.endTime = kLabelEndTimeS;
}

bool keepsLabelProtocol(const scene::MixerScene& s) {
    return s.method != "lts" && std::abs(s.initialLoadingKg - kLabelDepositKg) < 1e-12 &&
           s.steadyResidence >= kLabelWindowResidence - 1e-12;
}

void judgeLabel(const scene::MixerScene& s, const std::filesystem::path& caseDir, nlohmann::json& r) {
    if (s.method == "lts") {
        r["protocol"] = "custom";
        r["label"] = false;
        r["not_label_because"] = "pseudo-time (lts) has no residence time";
        return;
    }
    const auto hist = post::readLoadingHistory(caseDir);
    std::vector<double> t, M;
    for (const auto& h : hist) t.push_back(h.t), M.push_back(h.loading);
    // Smoothed over the steady test's own base window (whole revolutions), so a paddle's passage is
    // not a change of level.
    const double W = r.value("window", s.steadyWindow(M.back()));
    const auto lv = post::levelHistory(t, M, s.feedKgS(), W, s.steadyWindow(), kLabelLevelBand);
    r["settled_at_s"] = lv.settledAt;
    r["settled_residence_times"] = lv.settledResidenceTimes;
    r["level_change_seen"] = lv.levelChangeSeen;
    const double loading = r.value("loading_kg", lv.finalLevel);
    if (r.contains("dense_loading_kg") && r["dense_loading_kg"].is_number() && loading > 0)
        r["dense_share"] = r["dense_loading_kg"].get<double>() / loading;
    const auto& g = s.geometry;
    r["level_m"] = scene::depositHeight(std::max(loading, 0.0) / s.bulkDensity(), g.radius(), g.length) + g.radius();

    const auto& start = r.value("start", nlohmann::json::object());
    // A run that continues its own kept progress (a lost run directory) keeps its first start.
    const bool continued = start.contains("continues_run_dir");
    const auto& first = continued ? start.value("first_start", nlohmann::json::object()) : start;
    const bool warm = first.contains("warm_from");
    const bool kept = keepsLabelProtocol(s) && !warm;
    r["protocol"] = kept ? kLabelProtocol : "custom";
    std::ostringstream why;
    if (!kept)
        why << (warm ? "started from another run's fields" : "not the protocol's start and windows");
    else if (!r.value("steady", false))
        why << "no steady verdict";
    else if (!r.value("powder_balance_ok", true))
        why << "powder not conserved";
    else if (lv.settledResidenceTimes < kLabelSettledResidenceTimes)
        why << "held its level for " << std::round(100 * lv.settledResidenceTimes) / 100 << " residence times, under "
            << kLabelSettledResidenceTimes;
    r["label"] = why.str().empty();
    if (!why.str().empty()) r["not_label_because"] = why.str();
}

}  // namespace mixload::run
