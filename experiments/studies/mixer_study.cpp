// SPDX-License-Identifier: GPL-3.0-or-later
#include "studies/mixer_study.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

#include "cases/meshed_geometry.hpp"
#include "common/atomic_file.hpp"
#include "common/process.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "post/mixer_results.hpp"
#include "run/foam_runner.hpp"
#include "run/mixer_job.hpp"
#include "run/run_dir.hpp"
#include "studies/methods_comparison.hpp"
#include "studies/run_pool.hpp"
#include "studies/study_rows.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {

std::string series(const nlohmann::json& r, const char* fixed, bool withStart) {
    std::ostringstream os;
    os << r["method"].get<std::string>() << ' ' << r["mesh"].get<std::string>() << ' ';
    if (withStart) os << "from " << r["initial_loading_kg"].get<double>() << " kg ";
    if (std::string(fixed) == "rpm") os << r["rpm"].get<double>() << " rpm";
    else os << r["feed_kg_h"].get<double>() << " kg/h";
    return os.str();
}

std::string plotStudy(const fs::path& out, const nlohmann::json& rows) {
    // Left: M against feed, one line per method/mesh/rpm. Right: M against rpm, one per feed.
    // Unsteady or leaking points are drawn hollow: they are not results.
    std::map<std::string, std::ostringstream> byFeed, byRpm;
    std::set<double> starts;
    for (const auto& r : rows) starts.insert(r["initial_loading_kg"].get<double>());
    const bool withStart = starts.size() > 1;
    for (const auto& r : rows) {
        if (!r.contains("loading_kg")) continue;
        const bool good = isResult(r);
        byFeed[series(r, "rpm", withStart)] << r["feed_kg_h"].get<double>() << ' ' << r["loading_kg"].get<double>()
                                 << ' ' << (good ? 7 : 6) << '\n';
        byRpm[series(r, "feed", withStart)] << r["rpm"].get<double>() << ' ' << r["loading_kg"].get<double>()
                                 << ' ' << (good ? 7 : 6) << '\n';
    }
    std::ostringstream gp;
    gp << "set terminal pngcairo size 1200,480 noenhanced\nset output 'study.png'\n"
       << "set multiplot layout 1,2\nset grid\nset key left top\nset ylabel 'loading M [kg]'\n";
    int k = 0;
    auto plot = [&](std::map<std::string, std::ostringstream>& data, const char* xlabel) {
        gp << "set xlabel '" << xlabel << "'\nplot ";
        bool first = true;
        for (auto& [name, d] : data) {
            const std::string file = "series" + std::to_string(k++) + ".dat";
            std::ofstream(out / file) << d.str();
            gp << (first ? "" : ", ") << "'" << file
               << "' using 1:2:3 with linespoints pt variable ps 1.5 lw 2 title '" << name << "'";
            first = false;
        }
        gp << '\n';
    };
    plot(byFeed, "feed [kg/h]  (hollow: not steady or powder not conserved)");
    plot(byRpm, "impeller speed [rpm]");
    gp << "unset multiplot\n";
    return runGnuplot(out, "study.gp", gp.str());
}

// M(t) of every run on one set of axes: how each run approached (or did not reach) its loading.
std::string plotHistories(const fs::path& out, const nlohmann::json& rows,
                          const std::vector<nlohmann::json>& histories) {
    std::ostringstream gp;
    // The key goes below the axes, and lines past the palette's 8 colours are dashed, so that a
    // dozen runs stay readable.
    gp << "set terminal pngcairo size 1000,750 noenhanced\nset output 'histories.png'\n"
       << "set grid\nset key below maxrows 6\nset xlabel 't [s] (lts: pseudo-time iteration)'\n"
       << "set ylabel 'loading M [kg]'\nplot ";
    bool first = true;
    for (size_t i = 0; i < histories.size(); ++i) {
        if (!histories[i].is_array() || histories[i].empty()) continue;
        const auto& r = rows[i];
        const std::string file = "history" + std::to_string(i) + ".dat";
        std::ofstream os(out / file);
        for (const auto& p : histories[i]) os << p[0].get<double>() << ' ' << p[1].get<double>() << '\n';
        std::ostringstream title;
        title << r["method"].get<std::string>() << ' ' << r["mesh"].get<std::string>() << ", "
              << r["rpm"].get<double>() << " rpm, " << r["feed_kg_h"].get<double>() << " kg/h, from "
              << r["initial_loading_kg"].get<double>() << " kg";
        gp << (first ? "" : ", ") << "'" << file << "' using 1:2 with lines lw 2 lc " << i % 8 + 1
           << " dt " << i / 8 % 5 + 1 << " title '" << title.str() << "'";
        first = false;
    }
    if (first) return "no run has a history";
    gp << '\n';
    return runGnuplot(out, "histories.gp", gp.str());
}


}  // namespace

std::vector<nlohmann::json> runMixerScenes(const std::vector<scene::MixerScene>& scenes, const fs::path& runs,
                                           int jobs, int np, bool progress, const std::string& label,
                                           const std::vector<fs::path>& warmFrom,
                                           std::optional<std::chrono::steady_clock::time_point> deadline) {
    if (!warmFrom.empty() && warmFrom.size() != scenes.size())
        throw std::logic_error("runMixerScenes: one warm start per scene, or none");
    // Each run would refuse a mesh that cannot cut its paddles; the study refuses before the first.
    for (const auto& s : scenes) cases::requireSceneGeometry(s);
    std::vector<std::string> suffix(scenes.size());
    for (size_t i = 0; i < warmFrom.size(); ++i) {
        if (warmFrom[i].empty()) continue;
        run::warmSourceTime(warmFrom[i]);  // refuse a bad source before any run
        // The source's canonical path names the start: the same source resumes the same runs.
        char tag[32];
        std::snprintf(tag, sizeof tag, "-warm-%016zx",
                      std::hash<std::string>{}(fs::weakly_canonical(warmFrom[i]).string()));
        suffix[i] = tag;
    }
    fs::create_directories(runs);
    std::vector<nlohmann::json> out(scenes.size());
    runPool<nlohmann::json>(
        scenes.size(), jobs, label, progress,
        [&](size_t i) {
            run::MixerJob job;
            job.scene = scenes[i];
            job.np = np;
            job.out = runs / (scenes[i].hash() + suffix[i]);
            if (!warmFrom.empty()) job.warmFrom = warmFrom[i];
            job.deadline = deadline;
            try {
                return run::runMixer(job);
            } catch (const NotStarted&) {
                return nlohmann::json{{"stopped", stopRequested() ? "not started: the study was asked to stop"
                                                                  : "not started: the study's time was up"}};
            } catch (const DeadlineReached&) {
                return nlohmann::json{{"stopped", std::string(stopRequested() ? "stopped on request" : "stopped at the study's deadline") +
                                                      "; it resumes from its last written time"}};
            } catch (const run::RunError& e) {
                return nlohmann::json{{"error", e.what()}};
            }
        },
        [&](size_t i, const nlohmann::json& r) {
            for (const char* k : {"loading_kg", "loading_std_kg", "steady", "steady_time_s", "outflow_kg_h",
                                  "powder_leak_kg_h", "powder_balance_ok", "rotor_zone_loading_kg",
                                  "dense_loading_kg", "warning", "end_time_s", "cells", "wall_seconds",
                                  "core_seconds", "error", "stopped", "run_dir", "history"})
                if (r.contains(k)) out[i][k] = r[k];
            // The impeller the run simulated, so that studies of two meshes are compared only if it
            // is one impeller (study fidelity).
            if (r.contains("mesh") && r["mesh"].contains("geometry")) out[i]["impeller"] = r["mesh"]["geometry"];
            if (r.contains("end_time_s")) out[i]["start_time_s"] = post::startTime(r);
        });
    return out;
}

namespace {

// The sliding-mesh runs' starts: the latest fields of the MRF run at the same point (same scene but
// the method), which runs first. An sm scene without such a twin in the study is refused before any
// run; one whose twin failed gets an error row instead of a run from another start.
std::vector<nlohmann::json> runSmFromMrf(const MixerStudy& study, const fs::path& runs) {
    const auto& scenes = study.scenes;
    std::map<std::string, size_t> mrfAt;  // scene hash -> index
    for (size_t j = 0; j < scenes.size(); ++j)
        if (scenes[j].method == "mrf") mrfAt[scenes[j].hash()] = j;
    std::vector<size_t> twin(scenes.size(), scenes.size());
    std::vector<size_t> first, second;
    for (size_t i = 0; i < scenes.size(); ++i) {
        if (scenes[i].method != "sm") {
            first.push_back(i);
            continue;
        }
        second.push_back(i);
        auto m = scenes[i];
        m.method = "mrf";
        if (const auto it = mrfAt.find(m.hash()); it != mrfAt.end()) twin[i] = it->second;
        if (twin[i] == scenes.size())
            throw InputError("sm-from-mrf", "sm at " + formatNumber(scenes[i].rpm) + " rpm, " +
                                                formatNumber(scenes[i].feedKgH) + " kg/h",
                             "a study that also runs mrf at every sm point (--methods mrf sm)");
    }
    const auto pick = [&](const std::vector<size_t>& idx) {
        std::vector<scene::MixerScene> s;
        for (size_t i : idx) s.push_back(scenes[i]);
        return s;
    };
    std::vector<nlohmann::json> results(scenes.size());
    const auto mrf = runMixerScenes(pick(first), runs, study.jobs, study.np, study.progress, "mixer study (mrf)", {},
                                    study.deadline);
    for (size_t k = 0; k < first.size(); ++k) results[first[k]] = mrf[k];
    // With --sm-down-feeds the sm points that differ only in feed form a chain, highest feed first:
    // that one starts from its MRF twin, each next one continues the sm run above it (same mesh and
    // speed: a restart at its time and angle, not a map). Otherwise every chain has one point.
    std::map<std::string, std::vector<size_t>> chains;
    for (size_t i : second) {
        auto key = scenes[i];
        if (study.smDownFeeds) key.feedKgH = 0;
        chains[key.hash()].push_back(i);
    }
    size_t waves = 0;
    for (auto& [key, chain] : chains) {
        std::sort(chain.begin(), chain.end(),
                  [&](size_t a, size_t b) { return scenes[a].feedKgH > scenes[b].feedKgH; });
        waves = std::max(waves, chain.size());
    }
    for (size_t w = 0; w < waves; ++w) {
        std::vector<size_t> startable;
        std::vector<fs::path> from;
        for (const auto& [key, chain] : chains) {
            if (w >= chain.size()) continue;
            const size_t i = chain[w];
            const auto& src = results[w == 0 ? twin[i] : chain[w - 1]];
            if (src.contains("run_dir") && !src.contains("error") && !src.contains("stopped")) {
                startable.push_back(i);
                from.push_back(src["run_dir"].get<std::string>());
            } else if (src.contains("stopped")) {
                results[i] = {{"stopped", w == 0 ? "waits for the MRF run at this point (not finished)"
                                                 : "waits for the sm run at the next higher feed (not finished)"}};
            } else {
                results[i] = {{"error", w == 0 ? "no MRF run at this point to start from (it failed)"
                                               : "no sm run at the next higher feed to continue (it failed)"}};
            }
        }
        const auto sm = runMixerScenes(pick(startable), runs, study.jobs, study.np, study.progress,
                                       w == 0 ? "mixer study (sm from mrf)" : "mixer study (sm, lower feeds)", from,
                                       study.deadline);
        for (size_t k = 0; k < startable.size(); ++k) {
            results[startable[k]] = sm[k];
            results[startable[k]]["start"] = w == 0 ? "mrf" : "sm";
        }
    }
    return results;
}

}  // namespace

nlohmann::json runMixerStudy(const MixerStudy& study) {
    for (const auto& s : study.scenes) cases::requireSceneGeometry(s);  // before any directory
    const fs::path runs = study.runs.empty() ? study.out / "runs" : study.runs;
    fs::create_directories(runs);
    fs::create_directories(study.out);
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& s : study.scenes)
        rows.push_back({{"method", s.method},
                        {"mesh", s.meshLabel()},
                        {"rpm", s.rpm},
                        {"feed_kg_h", s.feedKgH},
                        {"initial_loading_kg", s.initialLoadingKg},
                        {"scene_hash", s.hash()}});
    std::vector<nlohmann::json> histories(study.scenes.size());

    const auto results = study.smFromMrf ? runSmFromMrf(study, runs)
                                         : runMixerScenes(study.scenes, runs, study.jobs, study.np, study.progress,
                                                          "mixer study", {}, study.deadline);
    for (size_t i = 0; i < results.size(); ++i) {
        for (auto it = results[i].begin(); it != results[i].end(); ++it)
            if (it.key() != "history") rows[i][it.key()] = it.value();
        if (results[i].contains("history")) histories[i] = results[i]["history"];
    }

    std::ostringstream csv, md;
    csv << "method,mesh,cells,rpm,feed_kg_h,start,initial_loading_kg,loading_kg,loading_std_kg,steady,steady_time_s,"
           "outflow_kg_h,powder_leak_kg_h,powder_balance_ok,end_time_s,wall_seconds,core_seconds,"
           "rotor_zone_loading_kg,dense_loading_kg\n";
    md << "| method | mesh | cells | rpm | feed [kg/h] | start [kg] | M [kg] | std [kg] | in rotor zone "
          "| in dense cells | steady at [s] | outflow [kg/h] | leak [kg/h] | simulated | wall [s] | core [s] |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
    for (const auto& r : rows) {
        const std::string head = r["method"].get<std::string>() + " | " + r["mesh"].get<std::string>();
        if (!r.contains("loading_kg")) {
            md << "| " << head << " | | " << r["rpm"] << " | " << r["feed_kg_h"] << " | " << r["initial_loading_kg"]
               << " | " << (r.contains("stopped") ? "not finished: " + r["stopped"].get<std::string>() : std::string("failed: see run dir"))
               << " |||||||||\n";
            continue;
        }
        const bool steady = r["steady"].get<bool>();
        const nlohmann::json leak = r.value("powder_leak_kg_h", nlohmann::json());
        const nlohmann::json ok = r.value("powder_balance_ok", nlohmann::json());
        const nlohmann::json zone = r.value("rotor_zone_loading_kg", nlohmann::json());
        const auto share = [&](const nlohmann::json& part) {
            return part.is_null() ? part : nlohmann::json(100.0 * part.get<double>() / r["loading_kg"].get<double>());
        };
        const nlohmann::json dense = r.value("dense_loading_kg", nlohmann::json());
        csv << r["method"].get<std::string>() << ',' << r["mesh"].get<std::string>() << ','
            << r["cells"] << ',' << r["rpm"] << ',' << r["feed_kg_h"] << ',' << startOf(r) << ','
            << r["initial_loading_kg"] << ',' << r["loading_kg"] << ','
            << r["loading_std_kg"] << ',' << (steady ? "yes" : "no") << ','
            << (steady ? r["steady_time_s"].dump() : "") << ',' << r["outflow_kg_h"] << ','
            << (leak.is_null() ? "" : leak.dump()) << ','
            << (ok.is_null() ? "" : (ok.get<bool>() ? "yes" : "no")) << ',' << r["end_time_s"]
            << ',' << r["wall_seconds"] << ',' << r["core_seconds"] << ','
            << (zone.is_null() ? "" : zone.dump()) << ',' << (dense.is_null() ? "" : dense.dump()) << '\n';
        md << "| " << head << " | " << r["cells"] << " | " << r["rpm"] << " | " << r["feed_kg_h"]
           << " | " << (startOf(r) == "deposit" ? r["initial_loading_kg"].dump() : startLabel(startOf(r)))
           << " | " << tableCell(r["loading_kg"], "%.4f") << (steady ? "" : " (not steady)")
           << " | " << tableCell(r["loading_std_kg"], "%.1e") << " | " << tableCell(share(zone), "%.0f%%")
           << " | " << tableCell(share(dense), "%.0f%%") << " | "
           << (steady ? tableCell(r["steady_time_s"], "%.1f") : "-") << " | "
           << tableCell(r["outflow_kg_h"], "%.2f") << " | " << tableCell(leak, "%.3g")
           << (ok.is_null() || ok.get<bool>() ? "" : " (leaks)") << " | "
           << tableCell(r["end_time_s"], "%.4g") << (r["method"] == "lts" ? " it" : " s")
           << (r.value("start_time_s", 0.0) > 0 ? " (from " + tableCell(r["start_time_s"], "%.4g") + ")" : "") << " | "
           << tableCell(r["wall_seconds"], "%.0f") << " | " << tableCell(r["core_seconds"], "%.0f") << " |\n";
    }
    writeFileAtomic(study.out / "table.csv", csv.str());
    writeFileAtomic(study.out / "table.md", md.str());
    const std::string warn = plotStudy(study.out, rows);
    const std::string hwarn = plotHistories(study.out, rows, histories);
    nlohmann::json result = {{"rows", rows},
                             {"table_csv", (study.out / "table.csv").string()},
                             {"table_md", (study.out / "table.md").string()},
                             {"plot", warn.empty() ? (study.out / "study.png").string() : ""},
                             {"histories_plot", hwarn.empty() ? (study.out / "histories.png").string() : ""}};
    if (!warn.empty()) result["plot_warning"] = warn;
    if (!hwarn.empty()) result["histories_plot_warning"] = hwarn;
    size_t unfinished = 0;
    for (const auto& r : rows) unfinished += r.contains("stopped");
    result["unfinished"] = unfinished;
    result["stopped_at_max_hours"] = unfinished > 0;
    // A study with both mrf and sm at the same points also writes the paper's comparison.
    if (const auto pairs = compareMethods(rows); !pairs.empty()) {
        const std::string mwarn = writeMethodsComparison(study.out, pairs);
        result["methods"] = pairs;
        result["methods_md"] = (study.out / "methods.md").string();
        if (!mwarn.empty()) result["methods_plot_warning"] = mwarn;
    }
    writeFileAtomic(study.out / "study.json", result.dump(2));
    return result;
}

}  // namespace mixload::experiments
