// SPDX-License-Identifier: GPL-3.0-or-later
#include "check_plot.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"

namespace mixload::surrogates {

namespace {

struct Set {
    std::string title;
    const char* style;
    std::vector<const nlohmann::json*> runs;
};

double orNan(const nlohmann::json& v) { return v.is_number() ? v.get<double>() : NAN; }

}  // namespace

std::optional<std::filesystem::path> plotCheck(const nlohmann::json& check, const std::string& title,
                                               const std::filesystem::path& dir, std::string& warning) {
    Set inside{"hold-out, inside its 95% interval", "pt 7 ps 1.3 lc rgb '#1f77b4'", {}};
    Set outside{"hold-out, outside its 95% interval", "pt 5 ps 1.3 lc rgb '#d62728'", {}};
    Set loo{"training runs, leave-one-out", "pt 6 ps 1.0 lc rgb '#7f7f7f'", {}};
    // Pointers into `check` itself: the sets are read after these loops. A run without an interval
    // (in_ci95 null) is not drawn as a miss.
    for (const auto& e : check.at("holdout")) (e.at("in_ci95") == false ? outside : inside).runs.push_back(&e);
    for (const auto& e : check.at("loo").at("runs")) loo.runs.push_back(&e);

    double lo = INFINITY, hi = 0, intervalTop = 0;
    for (const Set* s : {&inside, &outside, &loo})
        for (const auto* e : s->runs) {
            for (double v : {(*e)["loading_kg"].get<double>(), (*e)["predicted_kg"].get<double>()})
                if (v > 0) lo = std::min(lo, v), hi = std::max(hi, v);
            intervalTop = std::max(intervalTop, orNan((*e)["ci95_kg"][1]));  // NaN (no interval) is skipped
        }
    if (!(hi > 0)) {
        warning = "no run with a positive loading to draw";
        return std::nullopt;
    }
    // The frame holds every interval's top too, unless one runs off by more than tenfold.
    const double top = std::max(hi * 1.5, std::min(intervalTop * 1.2, hi * 10));
    // Log axes: an interval reaching zero or below (a response surface's) is drawn to the frame.
    const double floor = lo / 3;
    std::ostringstream dat, plot;
    int index = 0;
    for (const Set* s : {&loo, &inside, &outside}) {
        if (s->runs.empty()) continue;
        dat << "# " << s->title << ": full-run M, predicted M, 95% interval low, high [kg]\n";
        for (const auto* e : s->runs) {
            const double m = (*e)["loading_kg"], p = (*e)["predicted_kg"];
            double a = orNan((*e)["ci95_kg"][0]), b = orNan((*e)["ci95_kg"][1]);
            if (std::isnan(a) || std::isnan(b)) a = b = p;
            dat << m << ' ' << p << ' ' << std::max(a, floor) << ' ' << std::max(b, floor) << '\n';
        }
        dat << "\n\n";
        plot << (index ? ", " : "plot ") << "'parity.dat' index " << index << " using 1:2:3:4 with yerrorbars " << s->style
             << " title '" << s->title << " (" << s->runs.size() << ")'";
        ++index;
    }
    std::filesystem::create_directories(dir);
    writeFileAtomic(dir / "parity.dat", dat.str());
    std::ostringstream gp;
    gp << "set logscale xy\nset format x '%g'\nset format y '%g'\nset grid\nset size square\n"
       << "set xrange [" << floor << ":" << top << "]\nset yrange [" << floor << ":" << top << "]\n"
       << "set xlabel 'M, full run [kg]'\nset ylabel 'M, model [kg] (bars: its 95% interval)'\n"
       << "set title \"" << title << "\" font ',10'\nset key top left box opaque font ',9'\n"
       << plot.str() << ", x with lines lw 1.5 lc rgb 'black' title 'model = full run', 1.1*x with lines dt 2 lc rgb 'dark-gray' "
       << "title '±10%', 0.9*x with lines dt 2 lc rgb 'dark-gray' notitle\n";
    return renderPng(dir, "parity", "pngcairo size 820,780 noenhanced", gp.str(), warning);
}

}  // namespace mixload::surrogates
