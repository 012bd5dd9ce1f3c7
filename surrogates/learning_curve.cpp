// SPDX-License-Identifier: GPL-3.0-or-later
#include "learning_curve.hpp"

#include <cmath>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "error_stats.hpp"

namespace mixload::surrogates {

std::vector<CurvePoint> learningCurve(const std::vector<Row>& train, const std::vector<Row>& holdout, const FitOptions& o,
                                      const std::vector<int>& sizes) {
    if (holdout.empty()) throw InputError("holdout", "0", "at least one run the models never see");
    std::vector<CurvePoint> out;
    for (int n : sizes) {
        if (n < 5 || n > static_cast<int>(train.size()))
            throw InputError("size", std::to_string(n), "5 .. " + std::to_string(train.size()) + " (the training runs)");
        const std::vector<Row> first(train.begin(), train.begin() + n);
        const auto m = Surrogate::fit(first, o, {});
        auto ws = m.makeWorkspace();
        ErrorStats s;
        for (const auto& r : holdout) {
            const auto p = m.predict(r.x, ws);
            s.add(r.m, p.m, p.lo, p.hi);
        }
        const auto ci = s.meanInterval90();
        CurvePoint c;
        c.n = n;
        c.mean = s.mean().get<double>();
        c.lo = ci.is_null() ? c.mean : ci[0].get<double>();
        c.hi = ci.is_null() ? c.mean : ci[1].get<double>();
        c.max = s.maxJson().get<double>();
        c.coverage = s.coverage().is_null() ? NAN : s.coverage().get<double>();
        c.looMean = m.validation()["mean_rel_error"].get<double>();
        out.push_back(c);
    }
    return out;
}

nlohmann::json powerLawOf(const std::vector<CurvePoint>& curve, double target) {
    if (curve.size() < 2) return nullptr;
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    const double k = static_cast<double>(curve.size());
    for (const auto& c : curve) {
        const double x = std::log(c.n), y = std::log(c.mean);
        sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    const double slope = (k * sxy - sx * sy) / (k * sxx - sx * sx), icpt = (sy - slope * sx) / k;
    nlohmann::json j{{"exponent", -slope}, {"coefficient", std::exp(icpt)}, {"target", target}};
    // Only a falling curve reaches a smaller error.
    j["runs_for_target"] = slope < 0 ? nlohmann::json(std::exp((std::log(target) - icpt) / slope)) : nlohmann::json();
    return j;
}

nlohmann::json writeLearningCurve(const std::vector<CurvePoint>& curve, const nlohmann::json& law, const std::string& label,
                                  const std::filesystem::path& dir) {
    std::ostringstream md, csv, dat;
    md << "| training runs | hold-out mean error | 90% bootstrap | max | 95% coverage | leave-one-out mean |\n|---|---|---|---|---|---|\n";
    csv << "n,holdout_mean,holdout_lo,holdout_hi,holdout_max,coverage95,loo_mean\n";
    const auto pct = [](double v) { return formatNumber(std::round(1000 * v) / 10) + "%"; };
    for (const auto& c : curve) {
        md << "| " << c.n << " | " << pct(c.mean) << " | " << pct(c.lo) << " – " << pct(c.hi) << " | " << pct(c.max) << " | "
           << (std::isnan(c.coverage) ? std::string("–") : pct(c.coverage)) << " | " << pct(c.looMean) << " |\n";
        csv << c.n << ',' << c.mean << ',' << c.lo << ',' << c.hi << ',' << c.max << ',' << c.coverage << ',' << c.looMean << '\n';
        dat << c.n << ' ' << c.mean << ' ' << c.lo << ' ' << c.hi << ' ' << c.looMean << '\n';
    }
    if (!law.is_null()) {
        md << "\nPower law over these sizes: mean error = " << formatNumber(law["coefficient"].get<double>()) << " n^-"
           << formatNumber(law["exponent"].get<double>());
        if (!law["runs_for_target"].is_null())
            md << "; " << pct(law["target"].get<double>()) << " would need about " << std::lround(law["runs_for_target"].get<double>())
               << " runs (an extrapolation of the fit)";
        md << ".\n";
    }
    std::filesystem::create_directories(dir);
    writeFileAtomic(dir / "curve.md", md.str());
    writeFileAtomic(dir / "curve.csv", csv.str());
    writeFileAtomic(dir / "curve.dat", dat.str());
    std::ostringstream gp;
    gp << "set logscale xy\nset title 'Learning curve: " << label
       << "'\nset xlabel 'training runs'\nset ylabel 'mean relative error'\nset key top right\nset grid\nset xrange [" << curve.front().n / 1.5
       << ":" << curve.back().n * 1.5 << "]\n"
       << "plot 'curve.dat' using 1:2:3:4 with yerrorlines lw 2 title 'hold-out (90% bootstrap)', '' using 1:5 with linespoints dt 2 title 'leave-one-out'";
    if (!law.is_null())
        gp << ", " << law["coefficient"].get<double>() << "*x**(-" << law["exponent"].get<double>() << ") dt 2 lw 2 lc rgb 'dark-gray' title 'power law'";
    gp << "\n";
    std::string warning;
    const auto png = renderPng(dir, "curve", "pngcairo size 800,520 noenhanced", gp.str(), warning);
    return {{"table", (dir / "curve.md").string()},
            {"plot", png ? nlohmann::json(png->string()) : nlohmann::json()},
            {"plot_warning", warning}};
}

}  // namespace mixload::surrogates
