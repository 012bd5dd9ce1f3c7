// SPDX-License-Identifier: GPL-3.0-or-later
#include "post/collapse_results.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "cases/collapse2d.hpp"
#include "common/gnuplot.hpp"
#include "post/monitor_history.hpp"
#include "run/foam_runner.hpp"

namespace mixload::post {

namespace fs = std::filesystem;

namespace {
fs::path monitorDir(const fs::path& caseDir) {
    return caseDir / "postProcessing" / cases::kCollapseMonitor;
}
}  // namespace

std::vector<CollapseSample> readCollapseHistory(const fs::path& caseDir) {
    auto out = readSegments<CollapseSample>(
        monitorDir(caseDir), "collapse.dat", [](std::istream& is, CollapseSample& s) {
            return static_cast<bool>(is >> s.t >> s.volume >> s.kineticEnergy >> s.front >> s.height);
        });
    if (out.empty())
        throw run::RunError("no collapse monitor history in " + monitorDir(caseDir).string());
    return out;
}

std::vector<std::pair<double, double>> readFinalProfile(const fs::path& caseDir) {
    const fs::path dir = monitorDir(caseDir) / "profiles";
    fs::path latest;
    double tLatest = -1;
    if (fs::exists(dir))
        for (const auto& e : fs::directory_iterator(dir)) {
            if (e.path().extension() != ".dat") continue;
            const double t = std::atof(e.path().stem().c_str());
            if (t > tLatest) tLatest = t, latest = e.path();
        }
    if (latest.empty()) throw run::RunError("no deposit profile in " + dir.string());
    std::vector<std::pair<double, double>> prof;
    std::ifstream is(latest);
    std::string line;
    while (std::getline(is, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ls(line);
        double x, h;
        if (ls >> x >> h) prof.emplace_back(x, h);
    }
    return prof;
}

bool collapseReachedRest(const fs::path& caseDir) {
    return fs::exists(monitorDir(caseDir) / "rest");
}

nlohmann::json collapseResult(const scene::CollapseScene& s, const fs::path& caseDir) {
    const auto hist = readCollapseHistory(caseDir);
    const double Li = s.length, Hi = s.height(), tStar = s.tStar();
    const double v0 = Li * Hi * s.dx();  // exact initial powder volume (2D slab of depth dx)
    const auto& last = hist.back();

    // Thin the history to about 200 points for the JSON; the full one stays in the run dir.
    nlohmann::json runout = nlohmann::json::array();
    const size_t stride = std::max<size_t>(1, hist.size() / 200);
    for (size_t i = 0; i < hist.size(); i += stride)
        runout.push_back({hist[i].t / tStar, (hist[i].front - Li) / Li});
    if ((hist.size() - 1) % stride != 0) runout.push_back({last.t / tStar, (last.front - Li) / Li});

    double maxVolErr = 0;
    for (const auto& h : hist) maxVolErr = std::max(maxVolErr, std::abs(h.volume - v0) / v0);

    const auto profile = readFinalProfile(caseDir);
    const bool touchesRight = !profile.empty() && profile.back().second > 0.5 * s.dx();

    return {{"runout_star", (last.front - Li) / Li},
            {"height_star", last.height / Hi},
            {"t_star", tStar},
            {"end_time", last.t},
            {"end_time_tstar", last.t / tStar},
            {"stopped_by", collapseReachedRest(caseDir) ? "rest" : "cap"},
            {"powder_mass_error", (last.volume - v0) / v0},
            {"powder_mass_error_max", maxVolErr},
            {"powder_reached_domain_end", touchesRight},
            {"cells", s.cells()},
            {"time_steps", hist.size()},
            {"runout_history", runout}};
}

std::string plotCollapse(const scene::CollapseScene& s, const fs::path& caseDir) {
    const auto hist = readCollapseHistory(caseDir);
    const auto profile = readFinalProfile(caseDir);
    const double Li = s.length, Hi = s.height(), tStar = s.tStar();
    std::ostringstream runout, deposit;
    for (const auto& h : hist) runout << h.t / tStar << ' ' << (h.front - Li) / Li << '\n';
    for (const auto& [x, h] : profile) deposit << x / Li << ' ' << h / Hi << '\n';
    {
        std::ofstream(caseDir / "runout.dat") << "# t/t* L*\n" << runout.str();
        std::ofstream(caseDir / "deposit.dat") << "# x/Li h/Hi\n" << deposit.str();
    }
    std::ostringstream gp;
    gp << "set terminal pngcairo size 1200,480 noenhanced\n"
       << "set output 'collapse.png'\nset multiplot layout 1,2 title '" << s.material.name
       << ", a = " << s.aspect << ", " << s.rheology << ", dx = Li/" << s.cellsPerLength << "'\n"
       << "set grid\nset xlabel 't / t*'\nset ylabel 'L* = (L - Li)/Li'\n"
       << "plot 'runout.dat' using 1:2 with lines lw 2 title 'runout'\n"
       << "set xlabel 'x / Li'\nset ylabel 'h / Hi'\nset yrange [0:1.05]\n"
       << "plot 'deposit.dat' using 1:2 with lines lw 2 title 'final deposit', "
       << "'-' using 1:2 with lines dt 2 title 'initial column'\n0 1\n1 1\n1 0\ne\n"
       << "unset multiplot\n";
    return runGnuplot(caseDir, "collapse.gp", gp.str());
}

}  // namespace mixload::post
