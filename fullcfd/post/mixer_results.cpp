// SPDX-License-Identifier: GPL-3.0-or-later
#include "post/mixer_results.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <regex>
#include <sstream>

#include "cases/mixer3d.hpp"
#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "post/monitor_history.hpp"
#include "run/foam_runner.hpp"
#include "steadyLoading.H"

namespace mixload::post {

namespace fs = std::filesystem;

namespace {
fs::path monitorDir(const fs::path& caseDir) {
    return caseDir / "postProcessing" / cases::kLoadingMonitor;
}
}  // namespace

std::vector<LoadingSample> readLoadingHistory(const fs::path& caseDir) {
    auto out = readSegments<LoadingSample>(
        monitorDir(caseDir), "loading.dat", [](std::istream& is, LoadingSample& s) {
            if (!(is >> s.t >> s.loading >> s.inflow >> s.outflow >> s.fed >> s.out >> s.maxPowderSpeed))
                return false;
            if (!(is >> s.zoneLoading)) s.zoneLoading = std::nan("");
            if (!(is >> s.denseLoading)) s.denseLoading = std::nan("");
            return true;
        });
    if (out.empty()) throw run::RunError("no loading history in " + monitorDir(caseDir).string());
    return out;
}

std::optional<nlohmann::json> readSteadyVerdict(const fs::path& caseDir) {
    const fs::path f = monitorDir(caseDir) / "steady";
    if (!fs::exists(f)) return std::nullopt;
    nlohmann::json v = nlohmann::json::object();
    std::ifstream is(f);
    std::string key;
    double value;
    while (is >> key >> value) v[key] = value;
    if (!v.contains("loading_kg")) return std::nullopt;
    return v;
}

nlohmann::json readCheckMesh(const fs::path& caseDir) {
    const std::string log = readFile(caseDir / "log.checkMesh");
    nlohmann::json m = nlohmann::json::object();
    std::smatch r;
    if (std::regex_search(log, r, std::regex(R"(\n\s*cells:\s+(\d+))"))) m["cells"] = std::stol(r[1]);
    if (std::regex_search(log, r, std::regex(R"(Mesh non-orthogonality Max:\s*([0-9.eE+-]+))")))
        m["max_non_orthogonality_deg"] = std::stod(r[1]);
    if (std::regex_search(log, r, std::regex(R"(Total volume = ([0-9.eE+-]+?)\.?\s)")))
        m["total_volume_m3"] = std::stod(r[1]);
    if (std::regex_search(log, r, std::regex(R"(Max skewness = ([0-9.eE+-]+))")))
        m["max_skewness"] = std::stod(r[1]);
    m["ok"] = log.find("Mesh OK.") != std::string::npos;
    m["failed_checks"] = 0;
    if (std::regex_search(log, r, std::regex(R"(Failed (\d+) mesh checks)")))
        m["failed_checks"] = std::stoi(r[1]);
    // Faces per patch, from the patch topology table: a patch the mesh resolves with no face (a feed
    // inlet smaller than the cells) passes checkMesh but breaks the solver's boundary conditions.
    const auto table = log.find("Patch               Faces");
    if (table != std::string::npos) {
        std::istringstream rows(log.substr(log.find('\n', table) + 1));
        nlohmann::json faces = nlohmann::json::object();
        for (std::string line; std::getline(rows, line);) {
            std::istringstream is(line);
            std::string name;
            long n = -1;
            if (!(is >> name >> n)) break;
            faces[name] = n;
        }
        m["patch_faces"] = faces;
    }
    return m;
}

nlohmann::json mixerResult(const scene::MixerScene& s, const fs::path& caseDir) {
    const auto hist = readLoadingHistory(caseDir);
    const auto verdict = readSteadyVerdict(caseDir);
    const bool lts = s.method == "lts";
    std::vector<double> t, M, C, Z, D;
    for (const auto& h : hist) {
        t.push_back(h.t);
        M.push_back(h.loading);
        C.push_back(h.out);
        Z.push_back(h.zoneLoading);
        D.push_back(h.denseLoading);
    }
    // The final window: the steady test's window, or as much of it as the run has.
    const double end = t.back();
    const double W = std::min(verdict && verdict->contains("window")
                                  ? (*verdict)["window"].get<double>()
                                  : s.steadyWindow(M.back()),
                              end - t.front());
    double mean = M.back(), stdev = 0, outflow = hist.back().outflow, zone = Z.back(), dense = D.back();
    if (W > 0) {
        mean = steady::windowMean(t, M, end - W, end);
        zone = steady::windowMean(t, Z, end - W, end);
        dense = steady::windowMean(t, D, end - W, end);
        const double sq = [&] {
            std::vector<double> d2;
            for (double m : M) d2.push_back((m - mean) * (m - mean));
            return steady::windowMean(t, d2, end - W, end);
        }();
        stdev = std::sqrt(std::max(0.0, sq));
        outflow = (steady::interpolate(t, C, end) - steady::interpolate(t, C, end - W)) / W;
    }
    const auto& first = hist.front();
    const auto& last = hist.back();
    // Powder balance: what came in minus what went out must be what the mixer gained. Relative to
    // the powder that passed through (or to the loading when nothing was fed).
    const double gained = last.loading - first.loading;
    const double fedSinceStart = last.fed - first.fed, outSinceStart = last.out - first.out;
    const double scale = std::max(fedSinceStart, std::max(1e-12, first.loading));
    nlohmann::json history = nlohmann::json::array();
    const size_t stride = std::max<size_t>(1, hist.size() / 400);
    for (size_t i = 0; i < hist.size(); i += stride) history.push_back({hist[i].t, hist[i].loading});
    if ((hist.size() - 1) % stride != 0) history.push_back({last.t, last.loading});

    nlohmann::json r{{"method", s.method},
                     {"loading_kg", mean},
                     {"loading_std_kg", stdev},
                     {"steady", verdict.has_value()},
                     {"steady_time_s", verdict ? nlohmann::json((*verdict)["time"]) : nlohmann::json()},
                     {"outflow_kg_h", outflow * 3600.0},
                     // The part of the loading that the rotor's frame moves (mrf, lts) or that
                     // turns with the mesh (sm); the rest rests in stationary cells.
                     {"rotor_zone_loading_kg", std::isfinite(zone) ? nlohmann::json(zone) : nlohmann::json()},
                     {"dense_loading_kg", std::isfinite(dense) ? nlohmann::json(dense) : nlohmann::json()},
                     {"feed_kg_h", s.feedKgH},
                     {"rpm", s.rpm},
                     {"initial_loading_kg", first.loading},
                     {"final_loading_kg", last.loading},
                     // A run continued from another run's time starts there, not at 0.
                     {"start_time_s", first.t},
                     {"end_time_s", end},
                     {"window", W},
                     {"time_unit", lts ? "iteration" : "s"},
                     // Pseudo-time moves each cell by its own step: flow sums are not masses there.
                     {"powder_balance_error",
                      lts ? nlohmann::json() : nlohmann::json((gained - (fedSinceStart - outSinceStart)) / scale)},
                     {"fed_kg", fedSinceStart},
                     {"max_powder_speed_m_s", [&] {
                          double v = 0;
                          for (const auto& h : hist) v = std::max(v, h.maxPowderSpeed);
                          return v;
                      }()},
                     {"out_kg", outSinceStart},
                     {"history", history}};
    if (!lts) {
        r["revolutions"] = end / s.revolutionTime();
        // Leak rate [kg/h, negative = lost], judged against the powder that moved plus a floor of
        // 1e-4 of the initial loading for numerical noise on a bed at rest.
        const double leak = gained - (fedSinceStart - outSinceStart);
        const double duration = std::max(1e-12, end - t.front());
        const bool ok =
            std::abs(leak) <= 0.01 * (fedSinceStart + outSinceStart) + 1e-4 * first.loading;
        r["powder_leak_kg_h"] = leak / duration * 3600.0;
        r["powder_balance_ok"] = ok;
        if (!ok) {
            std::ostringstream w;
            w << "powder is not conserved: " << std::abs(leak) << " kg " << (leak < 0 ? "lost" : "created")
              << " in " << duration << " s (" << std::abs(leak) / duration * 3600.0
              << " kg/h against a feed of " << s.feedKgH << " kg/h); do not trust this loading";
            r["warning"] = w.str();
        }
    }
    // Measured: filled from empty (1 cm mesh, 39 rpm, 5 kg/h) and at 162-254 rpm with 5 kg/h, no cell
    // ever held more than half powder, and the loading settled far below what any deposit gave.
    if (std::isfinite(dense) && dense < 0.5 * mean) {
        std::ostringstream w;
        w << "only " << static_cast<int>(std::round(100.0 * dense / std::max(mean, 1e-300)))
          << "% of the loading is in cells more than half powder: the powder layer is thinner than "
             "the mesh resolves, so this loading is not a bed the model describes; refine the mesh "
             "(--cell-size) or start from a deposit (--initial-loading-kg)";
        addWarning(r, w.str());
    }
    // Runs made before the monitor stopped diverged solutions: powder beyond the bound anywhere in
    // the history means the loading that followed is not the model's.
    if (!lts) {
        const double bound = s.divergedPowderSpeed();
        const auto blown = std::find_if(hist.begin(), hist.end(), [&](const auto& h) { return h.maxPowderSpeed > bound; });
        if (blown != hist.end()) {
            std::ostringstream w;
            w << "the solution diverged at t = " << blown->t << " s (powder at " << blown->maxPowderSpeed
              << " m/s, above " << bound << " m/s): this loading is not the model's";
            r["diverged"] = true;
            r["steady"] = false;
            r["steady_time_s"] = nullptr;
            addWarning(r, w.str());
        }
    }
    r["final_max_powder_speed_m_s"] = last.maxPowderSpeed;
    if (verdict && r["steady"].get<bool>()) r["steady_verdict"] = *verdict;
    return r;
}

double startTime(const nlohmann::json& result) {
    if (result.contains("start_time_s")) return result["start_time_s"].get<double>();
    const auto h = result.find("history");
    if (h != result.end() && h->is_array() && !h->empty()) return (*h)[0][0].get<double>();
    return 0.0;
}

void addWarning(nlohmann::json& result, const std::string& warning) {
    result["warning"] = result.contains("warning") ? result["warning"].get<std::string>() + "; " + warning : warning;
}

std::string plotLoading(const scene::MixerScene& s, const fs::path& caseDir) {
    const auto hist = readLoadingHistory(caseDir);
    {
        std::ofstream os(caseDir / "loading_history.dat");
        os << "# t loading_kg outflow_kg_h\n";
        for (const auto& h : hist) os << h.t << ' ' << h.loading << ' ' << h.outflow * 3600 << '\n';
    }
    const std::string tl = s.method == "lts" ? "pseudo-time iteration" : "t [s]";
    std::ostringstream gp;
    gp << "set terminal pngcairo size 1000,700 noenhanced\nset output 'loading.png'\n"
       << "set multiplot layout 2,1 title '" << s.name << ", " << s.method << ", " << s.rpm
       << " rpm, feed " << s.feedKgH << " kg/h, " << s.meshLabel() << " mesh'\n"
       << "set grid\nset xlabel '" << tl << "'\nset ylabel 'mixer loading M [kg]'\n"
       << "plot 'loading_history.dat' using 1:2 with lines lw 2 title 'M'\n"
       << "set ylabel 'powder flow [kg/h]'\n"
       << "plot 'loading_history.dat' using 1:3 with lines title 'outflow', " << s.feedKgH
       << " with lines dt 2 lw 2 title 'feed'\n"
       << "unset multiplot\n";
    return runGnuplot(caseDir, "loading.gp", gp.str());
}

}  // namespace mixload::post
