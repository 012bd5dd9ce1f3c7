// SPDX-License-Identifier: GPL-3.0-or-later
#include "sensitivity/input_plane.hpp"

#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"

namespace mixload::experiments {

using surrogates::kInputSpecs;
using surrogates::Point;

namespace {

bool physical(const Point& x) {
    try {
        surrogates::requirePhysical(x);
        return true;
    } catch (const InputError&) {
        return false;
    }
}

std::string pct(double v) {
    std::ostringstream s;
    s << std::showpos << std::fixed << std::setprecision(1) << 100 * v << '%';
    return s.str();
}

std::string kg(double v) { return std::isnan(v) ? "–" : formatNumber(v); }

}  // namespace

nlohmann::json inputPlane(const surrogates::Surrogate& model, const std::string& modelPath, const PlaneSpec& spec,
                          const std::filesystem::path& dir) {
    requireRange("n", spec.n, 5, 201);
    const auto& xs = kInputSpecs[spec.x.input];
    const auto& ys = kInputSpecs[spec.y.input];
    if (spec.x.input == spec.y.input) throw InputError("y", ys.name, "an input other than x (" + std::string(xs.name) + ")");
    for (const auto* a : {&spec.x, &spec.y})
        if (!(a->lo < a->hi) || (kInputSpecs[a->input].positive && a->lo <= 0))
            throw InputError(std::string(kInputSpecs[a->input].name) + " range", formatNumber(a->lo) + ":" + formatNumber(a->hi),
                             kInputSpecs[a->input].positive ? "0 < LO < HI" : "LO < HI");
    surrogates::requirePhysical(spec.base);
    for (const auto& a : spec.arrows) surrogates::requirePhysical(a.to);

    auto ws = model.makeWorkspace();
    const auto at = [&](double xv, double yv) {
        Point p = spec.base;
        p[spec.x.input] = xv;
        p[spec.y.input] = yv;
        return p;
    };
    std::ostringstream csv, grid;
    csv << xs.name << ',' << ys.name << ",loading_kg,lo_kg,hi_kg,in_training_box\n";
    size_t predicted = 0, outside = 0;
    double mMin = std::numeric_limits<double>::infinity(), mMax = -mMin;
    for (int j = 0; j < spec.n; ++j) {
        const double yv = spec.y.lo + (spec.y.hi - spec.y.lo) * j / (spec.n - 1);
        for (int i = 0; i < spec.n; ++i) {
            const double xv = spec.x.lo + (spec.x.hi - spec.x.lo) * i / (spec.n - 1);
            const Point p = at(xv, yv);
            if (!physical(p)) {
                grid << xv << ' ' << yv << " NaN\n";
                continue;
            }
            const auto pr = model.predict(p, ws);
            ++predicted;
            outside += !pr.inBox;
            mMin = std::min(mMin, pr.m), mMax = std::max(mMax, pr.m);
            csv << xv << ',' << yv << ',' << pr.m << ',' << pr.lo << ',' << pr.hi << ',' << (pr.inBox ? "true" : "false") << '\n';
            grid << xv << ' ' << yv << ' ' << pr.m << '\n';
        }
        grid << '\n';
    }

    const auto base = model.predict(spec.base, ws);
    nlohmann::json arrows = nlohmann::json::array();
    std::ostringstream md;
    md << "# M over (" << xs.name << ", " << ys.name << ")\n\nModel: " << modelPath << " (" << model.sourceLabel() << ").\n"
       << "Held at:";
    for (size_t k = 0; k < surrogates::kInputs; ++k)
        if (k != spec.x.input && k != spec.y.input) md << ' ' << kInputSpecs[k].name << " = " << formatNumber(spec.base[k]);
    md << ". " << predicted << " grid points, " << outside << " of them outside the model's training box.\n\n"
       << "Base (" << xs.name << " = " << formatNumber(spec.base[spec.x.input]) << ", " << ys.name << " = "
       << formatNumber(spec.base[spec.y.input]) << "): M = " << kg(base.m) << " kg (95% " << kg(base.lo) << " – " << kg(base.hi)
       << ")\n\n## Arrows\n\n| change | M base [kg] | M new [kg] | dM/M | 95% interval of dM/M | in box |\n|---|---|---|---|---|---|\n";
    for (const auto& a : spec.arrows) {
        const auto pb = model.predict(a.to, ws);
        const auto d = model.predictDifference(spec.base, a.to);
        const double rel = d.dm / base.m;
        arrows.push_back({{"change", a.label},
                          {"to", {{xs.name, a.to[spec.x.input]}, {ys.name, a.to[spec.y.input]}}},
                          {"loading_kg", pb.m},
                          {"dm_kg", d.dm},
                          {"dm_rel", rel},
                          {"dm_ci95_kg", std::isnan(d.lo) ? nlohmann::json() : nlohmann::json{d.lo, d.hi}},
                          {"in_training_box", pb.inBox}});
        md << "| " << a.label << " | " << kg(base.m) << " | " << kg(pb.m) << " | " << pct(rel) << " | "
           << (std::isnan(d.lo) ? "–" : pct(d.lo / base.m) + " – " + pct(d.hi / base.m)) << " | " << (pb.inBox ? "yes" : "no")
           << " |\n";
    }

    // Full runs on the plane: every input but the two axes' at the base's value.
    nlohmann::json checks = nlohmann::json::array();
    // Runs at the same point of the plane (replicates, or a bed on either of two levels) share one
    // square and one label listing their loadings, which would otherwise print over each other.
    std::map<std::pair<double, double>, std::string> squares;
    double sumAbs = 0;
    int inside = 0;
    if (spec.checks) {
        md << "\n## Full runs on the plane\n\n| run | " << xs.name << " | " << ys.name
           << " | full M [kg] | model M [kg] | 95% interval | error |\n|---|---|---|---|---|---|---|\n";
        for (const auto& r : spec.checks->rows) {
            bool on = true;
            for (size_t k = 0; k < surrogates::kInputs; ++k)
                if (k != spec.x.input && k != spec.y.input &&
                    std::abs(r.x[k] - spec.base[k]) > spec.onPlaneTol * std::abs(spec.base[k]))
                    on = false;
            if (!on) continue;
            const auto pr = model.predict(r.x, ws);
            const double err = (pr.m - r.m) / r.m;
            const bool covered = !std::isnan(pr.lo) && r.m >= pr.lo && r.m <= pr.hi;
            sumAbs += std::abs(err);
            inside += covered;
            checks.push_back({{"id", r.id},
                              {xs.name, r.x[spec.x.input]},
                              {ys.name, r.x[spec.y.input]},
                              {"full_kg", r.m},
                              {"model_kg", pr.m},
                              {"ci95_kg", std::isnan(pr.lo) ? nlohmann::json() : nlohmann::json{pr.lo, pr.hi}},
                              {"rel_error", err},
                              {"covered", covered}});
            md << "| " << r.id << " | " << formatNumber(r.x[spec.x.input]) << " | " << formatNumber(r.x[spec.y.input]) << " | "
               << kg(r.m) << " | " << kg(pr.m) << " | " << kg(pr.lo) << " – " << kg(pr.hi) << " | " << pct(err) << " |\n";
            std::ostringstream label;
            label << std::setprecision(3) << r.m;
            auto& sq = squares[{r.x[spec.x.input], r.x[spec.y.input]}];
            sq += (sq.empty() ? "" : ", ") + label.str();
        }
        if (checks.empty()) md << "\n(none of the table's " << spec.checks->rows.size() << " runs lies on the plane)\n";
        else
            md << "\nMean |error| " << pct(sumAbs / checks.size()).substr(1) << " over " << checks.size() << " runs; " << inside
               << " inside the model's 95% interval.\n";
    }

    std::filesystem::create_directories(dir);
    writeFileAtomic(dir / "plane.csv", csv.str());
    writeFileAtomic(dir / "plane.md", md.str());
    writeFileAtomic(dir / "plane-grid.dat", grid.str());
    std::ostringstream pts;
    for (const auto& [xy, label] : squares) pts << xy.first << ' ' << xy.second << " \"" << label << "\"\n";
    writeFileAtomic(dir / "plane-checks.dat", pts.str());
    std::ostringstream gp;
    gp << "set title 'M [kg] from " << model.sourceLabel() << "' noenhanced\nset view map\nset pm3d map\n"
       << "set xlabel '" << xs.name << " [" << xs.unit << "]' noenhanced\nset ylabel '" << ys.name << " [" << ys.unit
       << "]' noenhanced\nset xrange [" << spec.x.lo << ':' << spec.x.hi << "]\nset yrange [" << spec.y.lo << ':' << spec.y.hi
       << "]\nset cblabel 'M [kg]'\nset palette rgb 33,13,10\nset key off\n"
       << (predicted && mMax > mMin ? "set cbrange [" + std::to_string(mMin) + ":" + std::to_string(mMax) + "]\n" : std::string())
       << (checks.empty() ? "" : "set xlabel offset 0,0.3\nset label 99 'white squares: full runs on the plane, their M [kg]' at graph 0,-0.13 noenhanced\n")
       << "set label 1 'base' at " << spec.base[spec.x.input] << ',' << spec.base[spec.y.input] << " point pt 7 ps 1.2 offset 0.5,-0.8 front\n";
    // Each arrow's label sits below its tip, one row further down per arrow: above the tip sits the
    // label of a full run at that point, and two tips at one height would print over each other.
    for (size_t i = 0; i < spec.arrows.size(); ++i) {
        const auto& a = spec.arrows[i];
        gp << "set arrow from " << spec.base[spec.x.input] << ',' << spec.base[spec.y.input] << ",0 to " << a.to[spec.x.input] << ','
           << a.to[spec.y.input] << ",0 front lw 2 lc rgb 'black'\nset label " << i + 2 << " '" << a.label << "' at "
           << a.to[spec.x.input] << ',' << a.to[spec.y.input] << " offset 0.5," << -1.2 * static_cast<double>(i + 1)
           << " front noenhanced\n";
    }
    gp << "splot 'plane-grid.dat' using 1:2:3 with pm3d lw 1";
    if (!checks.empty())
        gp << ", 'plane-checks.dat' using 1:2:(0) with points pt 5 ps 1.3 lc rgb 'white', "
              "'' using 1:2:(0):3 with labels offset 0,1 tc rgb 'white'";
    gp << '\n';
    std::string warning;
    const auto png = renderPng(dir, "plane", "pngcairo size 900,700 noenhanced", gp.str(), warning);

    nlohmann::json out{{"model", modelPath},
                       {"source", model.sourceLabel()},
                       {"x", {{"input", xs.name}, {"lo", spec.x.lo}, {"hi", spec.x.hi}}},
                       {"y", {{"input", ys.name}, {"lo", spec.y.lo}, {"hi", spec.y.hi}}},
                       {"grid_points", predicted},
                       {"outside_training_box", outside},
                       {"loading_range_kg", predicted ? nlohmann::json{mMin, mMax} : nlohmann::json()},
                       {"base_kg", base.m},
                       {"arrows", arrows},
                       {"checks", checks},
                       {"table", (dir / "plane.md").string()},
                       {"csv", (dir / "plane.csv").string()},
                       {"plot", png ? nlohmann::json(png->string()) : nlohmann::json()},
                       {"plot_warning", warning}};
    if (!checks.empty()) out["checks_mean_abs_error"] = sumAbs / checks.size(), out["checks_covered"] = inside;
    return out;
}

}  // namespace mixload::experiments
