// SPDX-License-Identifier: GPL-3.0-or-later
#include "studies/methods_comparison.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "post/mixer_results.hpp"
#include "studies/study_rows.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {
// The paper's MRF loadings lie 14-18% below its sliding-mesh ones (Table 3, eight cases).
constexpr double kPaperLow = -18.0, kPaperHigh = -14.0;

nlohmann::json costOf(const nlohmann::json& r) {
    const double wall = r.value("wall_seconds", 0.0), sim = r.value("end_time_s", 0.0) - post::startTime(r);
    return {{"wall_s", wall}, {"wall_per_simulated_s", sim > 0 ? nlohmann::json(wall / sim) : nlohmann::json()}};
}

}  // namespace

nlohmann::json compareMethods(const nlohmann::json& rows) {
    using Key = std::tuple<std::string, double, double, double>;
    std::map<Key, std::pair<const nlohmann::json*, const nlohmann::json*>> points;
    for (const auto& r : rows) {
        const std::string m = r.value("method", "");
        if ((m != "mrf" && m != "sm") || !r.contains("loading_kg")) continue;
        const Key k{r["mesh"].get<std::string>(), r["rpm"].get<double>(), r["feed_kg_h"].get<double>(),
                    r.value("initial_loading_kg", 0.0)};
        (m == "mrf" ? points[k].first : points[k].second) = &r;
    }
    nlohmann::json out = nlohmann::json::array();
    for (const auto& [k, p] : points) {
        if (!p.first || !p.second) continue;
        const auto &mrf = *p.first, &sm = *p.second;
        const double mm = mrf["loading_kg"].get<double>(), ms = sm["loading_kg"].get<double>();
        out.push_back({{"mesh", std::get<0>(k)},
                       {"rpm", std::get<1>(k)},
                       {"feed_kg_h", std::get<2>(k)},
                       {"initial_loading_kg", std::get<3>(k)},
                       {"mrf_loading_kg", mm},
                       {"sm_loading_kg", ms},
                       {"mrf_below_sm_percent", 100.0 * (mm - ms) / ms},
                       {"both_results", isResult(mrf) && isResult(sm)},
                       {"mrf_cost", costOf(mrf)},
                       {"sm_cost", costOf(sm)},
                       {"sm_start", startOf(sm)},
                       {"in_paper_band", 100.0 * (mm - ms) / ms >= kPaperLow && 100.0 * (mm - ms) / ms <= kPaperHigh}});
    }
    return out;
}

std::string writeMethodsComparison(const fs::path& out, const nlohmann::json& pairs) {
    std::ostringstream csv, md;
    csv << "mesh,rpm,feed_kg_h,initial_loading_kg,mrf_loading_kg,sm_loading_kg,mrf_below_sm_percent,"
           "both_results,mrf_wall_s,sm_wall_s,mrf_wall_per_simulated_s,sm_wall_per_simulated_s,sm_start\n";
    md << "MRF against the sliding mesh (SM), same scene, mesh and settings. The paper: MRF "
       << -kPaperHigh << "–" << -kPaperLow << "% below SM.\n\n"
       << "| mesh | rpm | feed [kg/h] | M MRF [kg] | M SM [kg] | (MRF − SM)/SM | both results | "
          "wall per simulated s MRF / SM | wall to verdict MRF / SM [s] | SM started from |\n"
          "|---|---|---|---|---|---|---|---|---|---|\n";
    std::map<double, std::ostringstream> loadings, diffs;
    double maxFeed = 0;
    for (const auto& p : pairs) {
        const bool ok = p["both_results"].get<bool>();
        const auto &cm = p["mrf_cost"], &cs = p["sm_cost"];
        csv << p["mesh"].get<std::string>() << ',' << p["rpm"] << ',' << p["feed_kg_h"] << ','
            << p["initial_loading_kg"] << ',' << p["mrf_loading_kg"] << ',' << p["sm_loading_kg"] << ','
            << p["mrf_below_sm_percent"] << ',' << (ok ? "yes" : "no") << ',' << cm["wall_s"] << ','
            << cs["wall_s"] << ',' << cm["wall_per_simulated_s"] << ',' << cs["wall_per_simulated_s"] << ','
            << p["sm_start"].get<std::string>() << '\n';
        md << "| " << p["mesh"].get<std::string>() << " | " << p["rpm"] << " | " << p["feed_kg_h"] << " | "
           << tableCell(p["mrf_loading_kg"], "%.4f") << " | " << tableCell(p["sm_loading_kg"], "%.4f") << " | "
           << tableCell(p["mrf_below_sm_percent"], "%+.1f%%") << " | "
           << (ok ? "yes" : "no (not steady or not conserved)") << " | "
           << tableCell(cm["wall_per_simulated_s"], "%.1f") << " / " << tableCell(cs["wall_per_simulated_s"], "%.1f")
           << " | " << tableCell(cm["wall_s"], "%.0f") << " / " << tableCell(cs["wall_s"], "%.0f") << " | "
           << startLabel(p["sm_start"])
           << (p["sm_start"] == "mrf"  ? " (its wall time adds to SM's)"
               : p["sm_start"] == "sm" ? " (its wall time adds to this one's)"
                                       : "")
           << " |\n";
        const double rpm = p["rpm"].get<double>(), feed = p["feed_kg_h"].get<double>();
        maxFeed = std::max(maxFeed, feed);
        loadings[rpm] << feed << ' ' << p["mrf_loading_kg"].get<double>() << ' '
                      << p["sm_loading_kg"].get<double>() << '\n';
        diffs[rpm] << feed << ' ' << p["mrf_below_sm_percent"].get<double>() << ' ' << (ok ? 7 : 6) << '\n';
    }
    writeFileAtomic(out / "methods.csv", csv.str());
    writeFileAtomic(out / "methods.md", md.str());
    if (pairs.empty()) return "no operating point has both an mrf and an sm run";

    std::ostringstream gp;
    gp << "set terminal pngcairo size 1200,480 noenhanced\nset output 'methods.png'\n"
       << "set multiplot layout 1,2\nset grid\nset key left top\nset xlabel 'feed [kg/h]'\n"
       << "set xrange [0:" << 1.1 * maxFeed << "]\n"
       << "set ylabel 'loading M [kg]'\nplot ";
    int k = 0;
    for (auto& [rpm, d] : loadings) {
        const std::string file = "methods-m" + std::to_string(k) + ".dat";
        std::ofstream(out / file) << d.str();
        gp << (k ? ", " : "") << "'" << file << "' using 1:2 with linespoints lw 2 lc " << k + 1
           << " title 'MRF " << rpm << " rpm', '" << file << "' using 1:3 with linespoints lw 2 dt 2 lc "
           << k + 1 << " title 'SM " << rpm << " rpm'";
        ++k;
    }
    gp << "\nset ylabel '(M_MRF - M_SM) / M_SM [%]  (hollow: not both results)'\n"
       << "set style fill transparent solid 0.25 noborder\nplot '+' using 1:(" << kPaperLow << "):("
       << kPaperHigh << ") with filledcurves lc 'gray' title 'paper: MRF 14-18% below SM'";
    k = 0;
    for (auto& [rpm, d] : diffs) {
        const std::string file = "methods-d" + std::to_string(k) + ".dat";
        std::ofstream(out / file) << d.str();
        gp << ", '" << file << "' using 1:2:3 with linespoints pt variable ps 1.5 lw 2 lc " << k + 1
           << " title '" << rpm << " rpm'";
        ++k;
    }
    gp << "\nunset multiplot\n";
    return runGnuplot(out, "methods.gp", gp.str());
}

}  // namespace mixload::experiments
