// SPDX-License-Identifier: GPL-3.0-or-later
#include "bench/pareto.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "common/stats.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

void markParetoFront(std::vector<ParetoMethod>& ms) {
    for (auto& m : ms) {
        m.front = true;
        for (const auto& o : ms)
            if (&o != &m && o.seconds <= m.seconds && o.error <= m.error && (o.seconds < m.seconds || o.error < m.error))
                m.front = false;
    }
}

nlohmann::json writePareto(const fs::path& out, const ParetoPlot& plot, std::vector<ParetoMethod>& ms) {
    markParetoFront(ms);
    std::ostringstream md, csv, dat;
    md << plot.caption << "\n\n" << std::setprecision(3) << "| method | online time per answer [s] |";
    for (const auto& h : plot.errorHeads) md << ' ' << h << " |";
    md << " offline [s] | Pareto front |\n|---|---|";
    for (size_t k = 0; k < plot.errorHeads.size(); ++k) md << "---|";
    md << "---|---|\n";
    csv << "method,seconds";
    for (const auto& k : plot.errorKeys) csv << ',' << k;
    csv << ",offline_seconds,front\n";
    nlohmann::json rows = nlohmann::json::array();
    for (const auto& m : ms) {
        md << "| " << m.name << " | " << m.seconds << " |";
        csv << '"' << m.name << "\"," << m.seconds;
        nlohmann::json row{{"method", m.name}, {"seconds", m.seconds}, {"offline_seconds", m.offlineSeconds},
                           {"reference", m.reference}, {"front", m.front}};
        for (size_t k = 0; k < plot.errorKeys.size(); ++k) {
            const double e = k < m.errors.size() ? m.errors[k] : std::nan("");
            md << ' ' << (m.reference ? std::string("reference") : formatNumber(std::round(e * 1e5) / 1e3) + "%") << " |";
            csv << ',' << e;
            row[plot.errorKeys[k]] = std::isfinite(e) ? nlohmann::json(e) : nlohmann::json();
        }
        md << ' ' << m.offlineSeconds << " | " << (m.front ? "yes" : "") << " |\n";
        csv << ',' << m.offlineSeconds << ',' << (m.front ? 1 : 0) << '\n';
        rows.push_back(row);
    }
    // One series per method, named in the key: text beside the points overlapped wherever methods
    // share a time or an error. The front in order of time, the reference drawn at the error floor.
    std::vector<ParetoMethod> byTime = ms;
    std::sort(byTime.begin(), byTime.end(), [](const auto& a, const auto& c) { return a.seconds < c.seconds; });
    const double floor = 1e-4;
    for (const auto& m : byTime) dat << m.seconds << ' ' << std::max(m.error, floor) << "\n\n\n";
    for (const auto& m : byTime)
        if (m.front) dat << m.seconds << ' ' << std::max(m.error, floor) << '\n';
    fs::create_directories(out);
    writeFileAtomic(out / "pareto.md", md.str());
    writeFileAtomic(out / "pareto.csv", csv.str());
    writeFileAtomic(out / "pareto.dat", dat.str());
    std::ostringstream gp;
    gp << "set terminal pngcairo size 860,560 noenhanced\nset output 'pareto.png'\nset logscale xy\nset grid\n"
       << "set format x '1e%L'\nset format y '1e%L'\n"
       << "set xlabel '" << plot.timeLabel << "'\nset ylabel '" << plot.errorLabel << "'\n"
       << "set title '" << plot.title << " (reference drawn at " << floor << ")'\n"
       << "set offsets graph 0.1, graph 0.1, graph 0.2, graph 0.5\nset key inside left bottom font ',9' spacing 1.1 box opaque\nplot ";
    for (size_t i = 0; i < byTime.size(); ++i) {
        std::string title = byTime[i].name;
        std::replace(title.begin(), title.end(), '\'', ' ');
        gp << "'pareto.dat' index " << i << " using 1:2 with points pt " << 5 + 2 * (i % 5) << " ps 1.6 lc " << i + 1
           << " title '" << title << (byTime[i].front ? " *" : "") << "', ";
    }
    gp << "'' index " << byTime.size() << " using 1:2 with steps lw 2 lc 'red' title 'Pareto front (*)'\n";
    const std::string warning = runGnuplot(out, "pareto.gp", gp.str());
    nlohmann::json j{{"pareto", rows}, {"pareto_table", (out / "pareto.md").string()}, {"pareto_plot", (out / "pareto.png").string()}};
    if (!warning.empty()) j["pareto_warning"] = warning;
    return j;
}

}  // namespace mixload::experiments
