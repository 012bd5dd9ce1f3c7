// SPDX-License-Identifier: GPL-3.0-or-later
#include "post/verdict_replay.hpp"

#include <algorithm>
#include <cmath>

#include <gsl/gsl_cdf.h>
#include <gsl/gsl_statistics_double.h>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "post/mixer_results.hpp"
#include "run/foam_runner.hpp"
#include "steadyLoading.H"

namespace mixload::post {

namespace fs = std::filesystem;

BatchMeans batchMeans(const std::vector<double>& t, const std::vector<double>& M, double from, int batches) {
    if (t.size() < 2) throw run::RunError("too short a loading history for batch means");
    if (batches < 2) throw InputError("batches", std::to_string(batches), ">= 2");
    if (from >= t.back())
        throw InputError("from", formatNumber(from),
                         "a time before the history's end (" + formatNumber(t.back()) + " s)");
    from = std::max(from, t.front());
    BatchMeans b;
    b.from = from;
    b.batchLength = (t.back() - from) / batches;
    for (int i = 0; i < batches; ++i)
        b.means.push_back(steady::windowMean(t, M, from + i * b.batchLength, from + (i + 1) * b.batchLength));
    b.mean = gsl_stats_mean(b.means.data(), 1, b.means.size());
    b.halfWidth95 = gsl_cdf_tdist_Pinv(0.975, batches - 1) *
                    gsl_stats_sd_m(b.means.data(), 1, b.means.size(), b.mean) / std::sqrt(batches);
    return b;
}

nlohmann::json replayVerdicts(const fs::path& caseDir, double tol, double flowTol,
                              double residence, int batches, double from) {
    const fs::path sceneFile = caseDir / "scene.json";
    if (!fs::exists(sceneFile)) throw run::RunError("no scene.json in " + caseDir.string());
    const auto sc = nlohmann::json::parse(readFile(sceneFile))["scene"];
    const double rpm = sc.value("rpm", 0.0), feed = sc.value("feed_kg_h", 0.0) / 3600;
    const double revs = sc.value("steady_window_revs", 3.0);
    const double minTime = sc.value("min_time_s", 0.0);
    const double period = rpm > 0 ? 60.0 / rpm : 0.0;
    const double base = revs * (rpm > 0 ? period : 1.0);
    // The balance test reads windows of the base revolutions.

    const auto hist = readLoadingHistory(caseDir);
    std::vector<double> t, M, C;
    nlohmann::json windows, balance;
    for (const auto& h : hist) {
        // The monitor samples every 1/50 of its shortest window.
        if (!t.empty() && h.t - t.back() < base / 50) continue;
        t.push_back(h.t);
        M.push_back(h.loading);
        C.push_back(h.out);
        if (windows.is_null()) {
            const double W = steady::windowLength(base, period, residence, M.back(), feed);
            const auto v = steady::test(t, M, C, W, feed, tol, flowTol, minTime);
            if (v.steady) windows = {{"time_s", t.back()}, {"loading_kg", v.meanLoading}};
        }
        if (balance.is_null()) {
            const double W = steady::windowLength(base, period, 0, M.back(), feed);
            const double Wres = steady::windowLength(base, period, residence, M.back(), feed);
            const auto v = steady::testBalance(t, M, C, W, Wres, feed, tol, flowTol, minTime);
            if (v.steady)
                balance = {{"time_s", t.back()},
                           {"loading_kg", v.meanLoading},
                           {"relaxation_time_s", v.tau},
                           {"by_balance", v.byBalance}};
        }
    }
    if (t.size() < 2) throw run::RunError("too short a loading history in " + caseDir.string());
    // The final loading: the mean over the last window of the window test.
    const double W = std::min(steady::windowLength(base, period, residence, M.back(), feed),
                              t.back() - t.front());
    const double final = W > 0 ? steady::windowMean(t, M, t.back() - W, t.back()) : M.back();
    nlohmann::json out{{"run_dir", caseDir.string()},
                       {"rpm", rpm},
                       {"feed_kg_h", feed * 3600},
                       {"end_time_s", t.back()},
                       {"final_loading_kg", final},
                       {"windows", windows},
                       {"balance", balance}};
    if (batches >= 2) {
        // All samples, not the monitor's thinned ones: a batch mean is an integral.
        std::vector<double> ta, Ma;
        for (const auto& h : hist) ta.push_back(h.t), Ma.push_back(h.loading);
        const double start = from >= 0 ? from
                             : windows.is_null() ? 0.5 * (ta.front() + ta.back())
                                                 : windows["time_s"].get<double>();
        // A run the monitor stopped at its verdict has no history after it: the default start
        // leaves nothing to average, and the user gave no --from to blame.
        if (from < 0 && start >= ta.back())
            throw InputError("from", "the window test's verdict, " + formatNumber(start) + " s (the default)",
                             "a time before the history's end: this run stopped at its verdict; give --from");
        const auto b = batchMeans(ta, Ma, start, batches);
        out["long_time"] = {{"from_s", b.from},          {"batches", batches},
                            {"batch_s", b.batchLength},  {"batch_means_kg", b.means},
                            {"mean_kg", b.mean},         {"half_width_95_kg", b.halfWidth95}};
    }
    return out;
}

nlohmann::json replayAll(const std::vector<std::string>& runDirs, double tol, double flowTol,
                         double residence, int batches, double from) {
    nlohmann::json rows = nlohmann::json::array();
    int called = 0, falseSteady = 0, earlier = 0;
    for (const auto& d : runDirs) {
        auto r = replayVerdicts(d, tol, flowTol, residence, batches, from);
        const double final = r["final_loading_kg"].get<double>();
        for (const char* k : {"windows", "balance"})
            if (!r[k].is_null()) r[k]["error_vs_final"] = r[k]["loading_kg"].get<double>() / final - 1;
        if (!r["balance"].is_null()) {
            ++called;
            if (std::abs(r["balance"]["error_vs_final"].get<double>()) > tol) ++falseSteady;
            if (!r["windows"].is_null() &&
                r["balance"]["time_s"].get<double>() < r["windows"]["time_s"].get<double>())
                ++earlier;
        }
        rows.push_back(r);
    }
    return {{"runs", rows},
            {"balance_verdicts", called},
            {"balance_false_steady", falseSteady},
            {"balance_earlier_than_windows", earlier}};
}

}  // namespace mixload::post
