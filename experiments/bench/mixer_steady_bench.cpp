// SPDX-License-Identifier: GPL-3.0-or-later
#include "bench/mixer_steady_bench.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/input_error.hpp"
#include "common/stats.hpp"
#include "post/mixer_results.hpp"
#include "run/mixer_job.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {

std::string pointName(const std::pair<double, double>& p) {
    return formatNumber(p.first) + " rpm, " + formatNumber(p.second) + " kg/h";
}

nlohmann::json row(const std::string& setup, const std::pair<double, double>& point,
                   const nlohmann::json& r) {
    const auto& p = r["profile"];
    return {{"point", pointName(point)},
            {"rpm", point.first},
            {"feed_kg_h", point.second},
            {"setup", setup},
            {"start", r["start"]},
            {"steady", r["steady"]},
            {"wall_seconds", r["solver_wall_seconds"]},
            {"simulated_s", r["end_time_s"].get<double>() - post::startTime(r)},
            {"steps", p["steps"]},
            {"mean_delta_t_s", p["mean_delta_t_s"]},
            {"courant_mean", p["courant"]["mean"]},
            {"courant_max", p["courant"]["max"]},
            {"ms_per_step", p["stages"].is_null() ? nlohmann::json() : p["stages"]["ms_per_step"]},
            {"loading_kg", r["loading_kg"]},
            {"powder_leak_kg_h", r.value("powder_leak_kg_h", nlohmann::json())},
            {"dense_share", r.value("dense_loading_kg", 0.0) / std::max(r["loading_kg"].get<double>(), 1e-30)},
            {"run_dir", r["run_dir"]}};
}

}  // namespace

nlohmann::json runSteadyBench(const SteadyBench& b) {
    if (b.points.empty()) throw InputError("points", "(none)", "at least one rpm:feed point");
    scene::MixerScene base = b.scene;
    base.numerics = scene::MixerNumerics::named("legacy");
    // Every scene is built and checked before anything runs.
    std::vector<scene::MixerScene> current, legacy;
    for (const auto& [rpm, feed] : b.points) {
        scene::MixerScene s = b.scene;
        s.rpm = rpm;
        s.feedKgH = feed;
        s.validate();
        current.push_back(s);
        scene::MixerScene l = base;
        l.rpm = rpm;
        l.feedKgH = feed;
        l.validate();
        legacy.push_back(l);
    }
    if (!b.resume) fs::remove_all(b.out);
    auto run = [&](const scene::MixerScene& s, const fs::path& dir, const fs::path& warm) {
        run::MixerJob job;
        job.scene = s;
        job.np = b.np;
        job.out = dir;
        job.progress = b.progress;
        job.reuse = b.resume;
        job.profile = true;
        job.warmFrom = warm;
        return run::runMixer(job);
    };
    nlohmann::json rows = nlohmann::json::array();
    std::vector<double> baseWall, coldWall, warmWall;
    std::vector<nlohmann::json> baseResult(b.points.size()), coldResult(b.points.size());
    for (size_t i = 0; i < b.points.size(); ++i) {
        const std::string tag = "p" + std::to_string(i);
        if (b.baseline) {
            baseResult[i] = run(legacy[i], b.out / (tag + "-baseline"), {});
            rows.push_back(row("baseline (legacy, cold)", b.points[i], baseResult[i]));
            baseWall.push_back(baseResult[i]["solver_wall_seconds"].get<double>());
        }
        coldResult[i] = run(current[i], b.out / (tag + "-cold"), {});
        rows.push_back(row("current, cold", b.points[i], coldResult[i]));
        coldWall.push_back(coldResult[i]["solver_wall_seconds"].get<double>());
    }
    // Warm runs start from the same point's baseline field (the new numerics must keep that
    // answer), or without a baseline from the previous point's cold run (the last's for the first).
    if (b.warm && (b.baseline || b.points.size() > 1))
        for (size_t i = 0; i < b.points.size(); ++i) {
            const size_t from = b.baseline ? i : (i + b.points.size() - 1) % b.points.size();
            const auto& source = b.baseline ? baseResult[from] : coldResult[from];
            const auto r = run(current[i], b.out / ("p" + std::to_string(i) + "-warm"),
                               source["run_dir"].get<std::string>());
            rows.push_back(row(b.baseline ? "current, warm from the baseline"
                                          : "current, warm from " + pointName(b.points[from]),
                               b.points[i], r));
            warmWall.push_back(r["solver_wall_seconds"].get<double>());
        }
    // Loadings against the baseline's (or the cold current run's without a baseline).
    for (auto& r : rows) {
        for (size_t i = 0; i < b.points.size(); ++i) {
            if (r["point"] != pointName(b.points[i])) continue;
            const auto& ref = b.baseline ? baseResult[i] : coldResult[i];
            const double m0 = ref["loading_kg"].get<double>();
            r["loading_change"] = r["loading_kg"].get<double>() / m0 - 1;
        }
    }
    nlohmann::json summary{{"median_wall_seconds_current_cold", median(coldWall)}};
    if (!baseWall.empty()) {
        summary["median_wall_seconds_baseline"] = median(baseWall);
        summary["speed_up_cold"] = median(baseWall) / median(coldWall);
    }
    if (!warmWall.empty()) {
        summary["median_wall_seconds_current_warm"] = median(warmWall);
        if (!baseWall.empty()) summary["speed_up_warm"] = median(baseWall) / median(warmWall);
    }
    double worst = 0;
    for (const auto& r : rows) worst = std::max(worst, std::abs(r["loading_change"].get<double>()));
    summary["largest_loading_change"] = worst;
    return {{"benchmark", "mixer steady"},
            {"scene", b.scene.toJson()},
            {"np", b.np},
            {"runs", rows},
            {"summary", summary}};
}

std::string formatSteadyBench(const nlohmann::json& res) {
    std::ostringstream os;
    char buf[512];
    os << "mixer steady benchmark (" << res["scene"]["mesh"].get<std::string>() << ", cell "
       << formatNumber(res["scene"]["cell_size_m"].get<double>()) << " m, np " << res["np"] << ")\n";
    std::snprintf(buf, sizeof buf, "%-18s %-44s %9s %8s %7s %8s %9s %10s %8s %11s\n", "point", "setup",
                  "wall [s]", "flow [s]", "steps", "dt [ms]", "Co mean", "M [kg]", "dM", "leak [kg/h]");
    os << buf;
    for (const auto& r : res["runs"]) {
        std::snprintf(buf, sizeof buf, "%-18s %-44s %9.1f %8.2f %7ld %8.3f %9.3g %10.5f %+7.2f%% %11.2g%s\n",
                      r["point"].get<std::string>().c_str(), r["setup"].get<std::string>().c_str(),
                      r["wall_seconds"].get<double>(), r["simulated_s"].get<double>(),
                      r["steps"].get<long>(), 1e3 * r["mean_delta_t_s"].get<double>(),
                      r["courant_mean"].get<double>(), r["loading_kg"].get<double>(),
                      100 * r["loading_change"].get<double>(),
                      r["powder_leak_kg_h"].is_null() ? 0.0 : r["powder_leak_kg_h"].get<double>(),
                      r["steady"].get<bool>() ? "" : "  NOT STEADY");
        os << buf;
    }
    const auto& s = res["summary"];
    os << "median wall to the verdict:";
    for (const char* k : {"median_wall_seconds_baseline", "median_wall_seconds_current_cold",
                          "median_wall_seconds_current_warm"})
        if (s.contains(k)) {
            std::snprintf(buf, sizeof buf, " %s %.1f s;", k + 20, s[k].get<double>());
            os << buf;
        }
    for (const char* k : {"speed_up_cold", "speed_up_warm"})
        if (s.contains(k)) {
            std::snprintf(buf, sizeof buf, " %s %.2fx;", k, s[k].get<double>());
            os << buf;
        }
    std::snprintf(buf, sizeof buf, " largest loading change %.2f%%\n",
                  100 * s["largest_loading_change"].get<double>());
    os << buf;
    return os.str();
}

}  // namespace mixload::experiments
