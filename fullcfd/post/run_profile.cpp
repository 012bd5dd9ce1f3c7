// SPDX-License-Identifier: GPL-3.0-or-later
#include "post/run_profile.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include "cases/mixer3d.hpp"
#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "common/stats.hpp"
#include "post/monitor_history.hpp"
#include "run/foam_runner.hpp"

namespace mixload::post {

namespace fs = std::filesystem;

namespace {

double mean(const std::vector<double>& v) {
    if (v.empty()) return std::nan("");
    double s = 0;
    for (double x : v) s += x;
    return s / v.size();
}

nlohmann::json number(double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); }

// The value after `key` on a line, or NaN.
double after(const std::string& line, const std::string& key) {
    const auto at = line.find(key);
    if (at == std::string::npos) return std::nan("");
    return std::atof(line.c_str() + at + key.size());
}

double dictNumber(const std::string& text, const std::string& key) {
    std::smatch m;
    if (std::regex_search(text, m, std::regex("\\n" + key + "\\s+([0-9.eE+-]+)\\s*;")))
        return std::stod(m[1]);
    return std::nan("");
}

struct Peak {
    double t, co, x, y, z, alpha, speed;
    int region;
};

struct CourantRow {
    double t, dt, coMean;
    Peak flow, iface;
};

std::vector<CourantRow> readCourantRows(const fs::path& caseDir) {
    return readSegments<CourantRow>(
        caseDir / "postProcessing" / cases::kCourantProfile, "courant.dat",
        [](std::istream& is, CourantRow& r) {
            auto peak = [&](Peak& p) {
                return static_cast<bool>(is >> p.co >> p.x >> p.y >> p.z >> p.alpha >> p.speed >>
                                         p.region);
            };
            if (!(is >> r.t >> r.dt >> r.coMean)) return false;
            return peak(r.flow) && peak(r.iface);
        });
}

const char* regionName(int r) {
    switch (r) {
        case 0: return "rotor zone";
        case 1: return "end layer";
        case 2: return "ring outside the zone";
        default: return "none";
    }
}

const char* phaseName(double alpha) {
    return alpha < 0.01 ? "air" : alpha > 0.99 ? "powder" : "mixed";
}

// Where the peaks sat: shares of steps by region and phase, with the median speed there.
nlohmann::json peakSites(const std::vector<CourantRow>& rows, bool iface) {
    std::map<std::string, std::vector<const Peak*>> by;
    for (const auto& r : rows) {
        const Peak& p = iface ? r.iface : r.flow;
        if (p.region < 0) continue;
        by[std::string(regionName(p.region)) + ", " + phaseName(p.alpha)].push_back(&p);
    }
    nlohmann::json out = nlohmann::json::array();
    for (const auto& [site, ps] : by) {
        std::vector<double> speed, x, r, a;
        for (const Peak* p : ps) {
            speed.push_back(p->speed);
            x.push_back(p->x);
            r.push_back(std::hypot(p->y, p->z));
            a.push_back(p->alpha);
        }
        out.push_back({{"site", site},
                       {"share_of_steps", double(ps.size()) / rows.size()},
                       {"median_speed_m_s", median(speed)},
                       {"median_x_m", median(x)},
                       {"median_radius_m", median(r)},
                       {"median_alpha", median(a)}});
    }
    std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
        return a["share_of_steps"].template get<double>() > b["share_of_steps"].template get<double>();
    });
    return out;
}

// Stage timings from OpenFOAM's profiler (the last solver process's cumulative totals).
nlohmann::json stageTimes(const fs::path& caseDir) {
    const double latest = run::latestTime(caseDir);
    fs::path file;
    for (const auto& e : fs::directory_iterator(caseDir)) {
        if (!e.is_directory()) continue;
        const auto t = parseNumber(e.path().filename().string());
        if (t && std::abs(*t - latest) <= 1e-12 * std::max(1.0, latest) &&
            fs::exists(e.path() / "uniform" / "profiling"))
            file = e.path() / "uniform" / "profiling";
    }
    if (file.empty()) return nullptr;
    const std::string text = readFile(file);
    const std::regex entry(
        R"re(description\s+"([^"]+)";\s*calls\s+(\d+);\s*totalTime\s+([0-9.eE+-]+);)re");
    std::map<std::string, std::pair<double, double>> seen;  // description -> (calls, total)
    for (auto it = std::sregex_iterator(text.begin(), text.end(), entry); it != std::sregex_iterator();
         ++it) {
        auto& s = seen[(*it)[1]];
        s.first += std::stod((*it)[2]);
        s.second += std::stod((*it)[3]);
    }
    double loop = 0, steps = 0;
    for (const auto& [d, v] : seen)
        if (d.rfind("time.run()", 0) == 0) {
            loop = v.second;
            steps = v.first;
        }
    if (loop <= 0 || steps <= 0) return nullptr;
    const std::pair<const char*, const char*> stages[] = {
        {"alpha (MULES)", "mixload::alpha"},
        {"viscosity update", "mixload::viscosity"},
        {"momentum (incl. MRF terms)", "mixload::momentum"},
        {"pressure (p_rgh correctors)", "mixload::pressure"},
        {"mesh update", "mixload::meshUpdate"},
        {"monitors (function objects)", "functionObjects.execute()"}};
    nlohmann::json rows = nlohmann::json::array();
    double counted = 0;
    for (const auto& [label, key] : stages) {
        const auto it = seen.find(key);
        if (it == seen.end()) continue;
        counted += it->second.second;
        rows.push_back({{"stage", label},
                        {"ms_per_step", 1e3 * it->second.second / steps},
                        {"share", it->second.second / loop}});
    }
    rows.push_back({{"stage", "other (Courant, time step, writes)"},
                    {"ms_per_step", 1e3 * (loop - counted) / steps},
                    {"share", (loop - counted) / loop}});
    nlohmann::json solves = nlohmann::json::object();
    for (const auto& [d, v] : seen)
        if (d.rfind("fvMatrix::solve.", 0) == 0)
            solves[d.substr(16)] = {{"ms_per_step", 1e3 * v.second / steps},
                                    {"calls_per_step", v.first / steps}};
    return {{"steps", steps},
            {"ms_per_step", 1e3 * loop / steps},
            {"stages", rows},
            {"linear_solves", solves}};
}

}  // namespace

nlohmann::json readRunProfile(const fs::path& caseDir) {
    const fs::path log = caseDir / "log.interFoam";
    if (!fs::exists(log)) throw run::RunError("no solver log in " + caseDir.string());
    const std::string control = readFile(caseDir / "system" / "controlDict");
    const double maxCo = dictNumber(control, "maxCo"), maxAlphaCo = dictNumber(control, "maxAlphaCo"),
                 maxDeltaT = dictNumber(control, "maxDeltaT");

    // One pass over the log: the Courant numbers the solver used, the time steps, the solves.
    std::ifstream is(log);
    std::string line;
    std::vector<double> dts, coMax, coMean, acoMax;
    double co = std::nan(""), aco = std::nan(""), coMeanNow = std::nan("");
    std::map<std::string, std::pair<double, double>> iters;  // field -> (solves, iterations)
    std::map<std::string, int> limiter;
    double firstTime = std::nan(""), lastTime = std::nan("");
    long steps = 0;
    while (std::getline(is, line)) {
        if (line.rfind("Courant Number mean:", 0) == 0) {
            coMeanNow = after(line, "mean:");
            co = after(line, "max:");
        } else if (line.rfind("Interface Courant Number", 0) == 0) {
            aco = after(line, "max:");
        } else if (line.rfind("deltaT = ", 0) == 0) {
            const double dt = after(line, "deltaT = ");
            dts.push_back(dt);
            coMax.push_back(co);
            coMean.push_back(coMeanNow);
            acoMax.push_back(aco);
            // The bound that set this step: the one closest to its limit.
            const double f[3] = {co / maxCo, aco / maxAlphaCo, dt / maxDeltaT};
            const int k = static_cast<int>(std::max_element(f, f + 3) - f);
            limiter[k == 0 ? "flow Courant" : k == 1 ? "interface Courant" : "maxDeltaT"]++;
        } else if (line.rfind("Time = ", 0) == 0) {
            const double t = after(line, "Time = ");
            ++steps;
            if (std::isnan(firstTime)) firstTime = t;
            lastTime = t;
        } else if (const auto at = line.find("Solving for "); at != std::string::npos) {
            const auto comma = line.find(',', at);
            const std::string field = line.substr(at + 12, comma - at - 12);
            auto& it = iters[field];
            it.first += 1;
            it.second += after(line, "No Iterations");
        }
    }
    if (steps == 0) throw run::RunError("no time steps in " + log.string());

    // Local time stepping (lts) has no global time step: those entries stay null.
    nlohmann::json out;
    out["steps"] = steps;
    out["simulated_s"] = number(lastTime - firstTime);
    out["mean_delta_t_s"] = number(mean(dts));
    out["median_delta_t_s"] = number(median(dts));
    out["limits"] = {{"maxCo", number(maxCo)}, {"maxAlphaCo", number(maxAlphaCo)},
                     {"maxDeltaT_s", number(maxDeltaT)}};
    out["courant"] = {{"mean", number(mean(coMean))},
                      {"median_max", number(median(coMax))},
                      {"max", coMax.empty() ? nlohmann::json()
                                            : number(*std::max_element(coMax.begin(), coMax.end()))},
                      {"interface_median_max", number(median(acoMax))}};
    nlohmann::json lim = nlohmann::json::object();
    for (const auto& [k, n] : limiter) lim[k] = double(n) / std::max<size_t>(dts.size(), 1);
    out["step_set_by"] = lim;
    nlohmann::json solves = nlohmann::json::object();
    for (const auto& [field, v] : iters)
        solves[field] = {{"solves_per_step", v.first / steps},
                         {"iterations_per_solve", v.second / v.first}};
    out["solves"] = solves;

    const auto rows = readCourantRows(caseDir);
    if (rows.empty()) {
        out["flow_courant_peak"] = nullptr;
        out["interface_courant_peak"] = nullptr;
    } else {
        out["flow_courant_peak"] = peakSites(rows, false);
        out["interface_courant_peak"] = peakSites(rows, true);
    }
    out["stages"] = stageTimes(caseDir);
    return out;
}

std::string formatRunProfile(const nlohmann::json& p) {
    std::ostringstream os;
    char buf[256];
    auto val = [](const nlohmann::json& v, double scale = 1) {
        return v.is_null() ? std::nan("") : scale * v.get<double>();
    };
    std::snprintf(buf, sizeof buf,
                  "  profile: %ld steps over %.4g s, mean dt %.3g ms (limit %.3g ms); Courant mean "
                  "%.3g, median max %.3g, interface median max %.3g\n",
                  p["steps"].get<long>(), val(p["simulated_s"]), val(p["mean_delta_t_s"], 1e3),
                  val(p["limits"]["maxDeltaT_s"], 1e3), val(p["courant"]["mean"]),
                  val(p["courant"]["median_max"]), val(p["courant"]["interface_median_max"]));
    os << buf << "    time step set by:";
    for (const auto& [k, v] : p["step_set_by"].items()) {
        std::snprintf(buf, sizeof buf, " %s %.0f%%", k.c_str(), 100 * v.get<double>());
        os << buf;
    }
    os << '\n';
    for (const char* which : {"flow_courant_peak", "interface_courant_peak"}) {
        if (p[which].is_null() || p[which].empty()) continue;
        os << "    " << (std::string(which) == "flow_courant_peak" ? "largest flow Courant" : "largest interface Courant") << " at:";
        int shown = 0;
        for (const auto& s : p[which]) {
            if (shown++ == 3) break;
            std::snprintf(buf, sizeof buf, " %s %.0f%% (%.2g m/s, x %.3g m, r %.3g m);",
                          s["site"].get<std::string>().c_str(), 100 * s["share_of_steps"].get<double>(),
                          s["median_speed_m_s"].get<double>(), s["median_x_m"].get<double>(),
                          s["median_radius_m"].get<double>());
            os << buf;
        }
        os << '\n';
    }
    if (!p["stages"].is_null()) {
        std::snprintf(buf, sizeof buf, "    %.3g ms per step:", p["stages"]["ms_per_step"].get<double>());
        os << buf;
        for (const auto& s : p["stages"]["stages"]) {
            std::snprintf(buf, sizeof buf, " %s %.1f (%.0f%%);", s["stage"].get<std::string>().c_str(),
                          s["ms_per_step"].get<double>(), 100 * s["share"].get<double>());
            os << buf;
        }
        os << '\n';
    }
    os << "    iterations per solve:";
    for (const auto& [k, v] : p["solves"].items()) {
        std::snprintf(buf, sizeof buf, " %s %.1f (x%.1f per step);", k.c_str(),
                      v["iterations_per_solve"].get<double>(), v["solves_per_step"].get<double>());
        os << buf;
    }
    os << '\n';
    return os.str();
}

}  // namespace mixload::post
