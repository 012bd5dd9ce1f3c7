// SPDX-License-Identifier: GPL-3.0-or-later
#include "whatif/whatif.hpp"

#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "regime.hpp"

namespace mixload::experiments {

using surrogates::kInputSpecs;
using surrogates::Point;

nlohmann::json predictionJson(const surrogates::Surrogate& m, const surrogates::Point& x, const surrogates::Prediction& p,
                              const std::string& modelPath) {
    nlohmann::json j{{"loading_kg", p.m},
                     {"ci95_kg", std::isnan(p.lo) ? nlohmann::json() : nlohmann::json{p.lo, p.hi}},
                     {"in_training_box", p.inBox},
                     {"outside_distance", p.outside},
                     {"clipped_at_zero", p.clipped},
                     {"full_barrel_kg", p.fullBarrelKg > 0 ? nlohmann::json(p.fullBarrelKg) : nlohmann::json()},
                     {"above_full_barrel", p.overfull},
                     {"model", modelPath},
                     {"kind", m.kind()},
                     {"source", m.sourceLabel()}};
    if (!p.inBox) j["outside"] = m.outsideBox(x);
    j["regime"] = regimeErrorJson(m, x);
    return j;
}

nlohmann::json regimeErrorJson(const surrogates::Surrogate& m, const surrogates::Point& x) {
    const auto regime = surrogates::regimeOf(x);
    nlohmann::json j{{"name", surrogates::regimeName(regime)}, {"measured", nullptr}};
    // The latest check against hold-out runs of the model's own scene that has figures per regime
    // (`mixload check` records them); a check of another scene's runs records nothing.
    const auto& history = m.checkHistory();
    for (auto it = history.rbegin(); it != history.rend(); ++it) {
        if (!it->contains("holdout_by_regime")) continue;
        const auto& f = (*it)["holdout_by_regime"][surrogates::regimeName(regime)];
        if (f.value("n", 0) == 0) continue;
        j["measured"] = {{"n_holdout", f["n"]},
                         {"mean_rel_error", f["mean_rel_error"]},
                         {"mean_rel_error_ci90", f["mean_rel_error_ci90"]},
                         {"max_rel_error", f["max_rel_error"]},
                         {"coverage95", f["coverage95"]},
                         {"date_utc", it->value("date_utc", "")},
                         {"source", it->value("source", nlohmann::json())}};
        break;
    }
    return j;
}

std::string regimeErrorLine(const nlohmann::json& regime) {
    std::ostringstream os;
    const std::string name = regime["name"].get<std::string>();
    os << "regime: " << name << " ("
       << (name == "bed" ? "below 140 rpm" : name == "film" ? "above 205 rpm" : "140-205 rpm, where the start can pick the state") << "); ";
    const auto& f = regime["measured"];
    if (f.is_null()) {
        os << "this model's error there is not measured (mixload check --model MODEL --table HOLDOUT.csv)";
        return os.str();
    }
    const auto pct = [](const nlohmann::json& v) {
        std::ostringstream p;
        p << std::fixed << std::setprecision(1) << 100 * v.get<double>() << '%';
        return v.is_null() ? std::string("n/a") : p.str();
    };
    os << "this model's measured hold-out error there: mean " << pct(f["mean_rel_error"]) << ", max " << pct(f["max_rel_error"])
       << ", 95% coverage " << pct(f["coverage95"]) << " (" << f["n_holdout"].get<int>() << " runs of "
       << (f["source"].is_object() ? f["source"].value("campaign", f["source"].value("table", std::string("a table")))
                                   : std::string("a table"))
       << ", checked " << f["date_utc"].get<std::string>().substr(0, 10) << ")";
    return os.str();
}

nlohmann::json compareFormulations(const surrogates::Surrogate& m, const std::string& modelPath, const Point& base,
                                   const Point& changed, const std::vector<std::pair<double, double>>& operatingPoints,
                                   bool extrapolate) {
    std::vector<std::pair<Point, Point>> pairs;
    for (const auto& [feed, rpm] : operatingPoints) {
        Point xa = base, xb = changed;
        xa[surrogates::kFeed] = xb[surrogates::kFeed] = feed;
        xa[surrogates::kRpm] = xb[surrogates::kRpm] = rpm;
        surrogates::requirePhysical(xa);
        surrogates::requirePhysical(xb);
        if (!extrapolate) m.requireNearBox(xa, "base "), m.requireNearBox(xb, "new ");
        pairs.emplace_back(xa, xb);
    }
    auto ws = m.makeWorkspace();
    nlohmann::json points = nlohmann::json::array();
    for (const auto& [xa, xb] : pairs) {
        const double feed = xa[surrogates::kFeed], rpm = xa[surrogates::kRpm];
        const auto pa = m.predict(xa, ws), pb = m.predict(xb, ws);
        // The two predictions share most of their error: the interval of the difference comes
        // from their joint distribution (the independent one beside it, for comparison).
        const auto diff = m.predictDifference(xa, xb);
        const double dm = pb.m - pa.m;
        nlohmann::json attribution = nlohmann::json::array();
        double sum = 0;
        for (size_t k : kMaterial) {
            if (xa[k] == xb[k]) continue;
            Point xk = xa;
            xk[k] = xb[k];
            const double dk = m.predict(xk, ws).m - pa.m;  // this input alone, from the base
            sum += dk;
            attribution.push_back({{"input", kInputSpecs[k].name}, {"from", xa[k]}, {"to", xb[k]}, {"delta_kg", dk}});
        }
        points.push_back({{"feed_kg_h", feed},
                                 {"rpm", rpm},
                                 {"base", predictionJson(m, xa, pa, modelPath)},
                                 {"new", predictionJson(m, xb, pb, modelPath)},
                                 {"delta_kg", dm},
                                 {"delta_rel", dm / pa.m},
                                 {"delta_ci95_kg", std::isnan(diff.lo) ? nlohmann::json() : nlohmann::json{diff.lo, diff.hi}},
                                 {"delta_ci95_independent_kg",
                                  std::isnan(diff.lo) ? nlohmann::json() : nlohmann::json{diff.loIndependent, diff.hiIndependent}},
                                 {"error_correlation", diff.correlation},
                                 {"attribution", attribution},
                                 {"interaction_kg", dm - sum}});
    }
    return points;
}

nlohmann::json whatifReport(const surrogates::Surrogate& m, const std::string& modelPath, const Point& base, const Point& changed,
                            const std::vector<double>& feeds, const std::vector<double>& rpms, const std::filesystem::path& dir) {
    if (feeds.empty()) throw InputError("feeds", "(none)", "at least one feed [kg/h]");
    if (rpms.empty()) throw InputError("rpms", "(none)", "at least one speed [rpm]");
    std::vector<std::pair<double, double>> grid;
    for (double r : rpms)
        for (double f : feeds) grid.emplace_back(f, r);
    const auto points = compareFormulations(m, modelPath, base, changed, grid);  // validates every point first

    std::ostringstream md, csv, dat;
    md << "What-if over the operating map from `" << modelPath << "` (" << m.sourceLabel() << ").\n\n| | mu_s | mu_d | i0 | d [m] | rho [kg/m3] |\n|---|---|---|---|---|---|\n";
    for (const auto& [name, x] : {std::pair{"base", base}, std::pair{"new", changed}})
        md << "| " << name << " | " << formatNumber(x[0]) << " | " << formatNumber(x[1]) << " | " << formatNumber(x[2]) << " | "
           << formatNumber(x[3]) << " | " << formatNumber(x[4]) << " |\n";
    md << "\n| feed [kg/h] | rpm | M base [kg] (95%) | M new [kg] (95%) | dM [kg] (95%) | dM/M | largest driver | in box |\n"
          "|---|---|---|---|---|---|---|---|\n";
    // A loading above a full barrel of the powder cannot happen: such a row says so where it is read.
    csv << "feed_kg_h,rpm,m_base_kg,m_base_lo,m_base_hi,m_new_kg,m_new_lo,m_new_hi,delta_kg,delta_lo,delta_hi,delta_rel,driver,driver_kg,"
           "interaction_kg,in_box,above_full_barrel\n";
    // The table is read, not parsed (the CSV keeps every digit): four significant digits, about
    // a thousandth of the intervals' width.
    const auto sig = [](double v) {
        std::ostringstream os;
        os << std::setprecision(4) << v;
        return os.str();
    };
    const auto ci = [&](const nlohmann::json& v) { return v.is_null() ? std::string("–") : sig(v[0]) + " – " + sig(v[1]); };
    const auto lo = [](const nlohmann::json& v) { return v.is_null() ? NAN : v[0].get<double>(); };
    const auto hi = [](const nlohmann::json& v) { return v.is_null() ? NAN : v[1].get<double>(); };
    double lastRpm = NAN;
    for (const auto& p : points) {
        std::string driver = "–";
        double driverKg = 0;
        for (const auto& a : p["attribution"])
            if (std::abs(a["delta_kg"].get<double>()) > std::abs(driverKg)) driverKg = a["delta_kg"], driver = a["input"];
        const bool inBox = p["base"]["in_training_box"].get<bool>() && p["new"]["in_training_box"].get<bool>();
        const bool overfull = p["base"]["above_full_barrel"].get<bool>() || p["new"]["above_full_barrel"].get<bool>();
        const double feed = p["feed_kg_h"], rpm = p["rpm"];
        md << "| " << formatNumber(feed) << " | " << formatNumber(rpm) << " | " << sig(p["base"]["loading_kg"]) << " ("
           << ci(p["base"]["ci95_kg"]) << ") | " << sig(p["new"]["loading_kg"]) << " (" << ci(p["new"]["ci95_kg"]) << ") | "
           << sig(p["delta_kg"]) << " (" << ci(p["delta_ci95_kg"]) << ") | " << std::showpos << std::fixed << std::setprecision(1)
           << 100 * p["delta_rel"].get<double>() << std::noshowpos << std::defaultfloat << std::setprecision(6) << "% | " << driver << " ("
           << sig(driverKg) << " kg) | " << (inBox ? "yes" : "no") << (overfull ? "; above a full barrel: not valid" : "") << " |\n";
        csv << feed << ',' << rpm << ',' << p["base"]["loading_kg"].get<double>() << ',' << lo(p["base"]["ci95_kg"]) << ','
            << hi(p["base"]["ci95_kg"]) << ',' << p["new"]["loading_kg"].get<double>() << ',' << lo(p["new"]["ci95_kg"]) << ','
            << hi(p["new"]["ci95_kg"]) << ',' << p["delta_kg"].get<double>() << ',' << lo(p["delta_ci95_kg"]) << ','
            << hi(p["delta_ci95_kg"]) << ',' << p["delta_rel"].get<double>() << ',' << driver << ',' << driverKg << ','
            << p["interaction_kg"].get<double>() << ',' << (inBox ? "true" : "false") << ',' << (overfull ? "true" : "false") << '\n';
        if (!std::isnan(lastRpm) && rpm != lastRpm) dat << "\n\n";  // one gnuplot data block per speed
        lastRpm = rpm;
        dat << feed << ' ' << rpm << ' ' << p["base"]["loading_kg"].get<double>() << ' ' << lo(p["base"]["ci95_kg"]) << ' '
            << hi(p["base"]["ci95_kg"]) << ' ' << p["new"]["loading_kg"].get<double>() << ' ' << lo(p["new"]["ci95_kg"]) << ' '
            << hi(p["new"]["ci95_kg"]) << ' ' << p["delta_kg"].get<double>() << ' ' << lo(p["delta_ci95_kg"]) << ' '
            << hi(p["delta_ci95_kg"]) << '\n';
    }
    std::filesystem::create_directories(dir);
    writeFileAtomic(dir / "report.md", md.str());
    writeFileAtomic(dir / "report.csv", csv.str());
    writeFileAtomic(dir / "report.dat", dat.str());
    std::ostringstream gp, mPlot, dPlot;
    for (size_t i = 0; i < rpms.size(); ++i) {
        const std::string sep = i ? ", " : "", idx = " index " + std::to_string(i);
        mPlot << sep << "'report.dat'" << idx << " using 1:3:4:5 with yerrorlines lc " << i + 1 << " dt 1 title '" << formatNumber(rpms[i])
              << " rpm', 'report.dat'" << idx << " using 1:6:7:8 with yerrorlines lc " << i + 1 << " dt 2 notitle";
        dPlot << sep << "'report.dat'" << idx << " using 1:9:10:11 with yerrorlines lc " << i + 1 << " title '" << formatNumber(rpms[i]) << " rpm'";
    }
    gp << "set multiplot layout 1,2 title 'What-if from "
       << m.sourceLabel() << "'\nset xlabel 'feed [kg/h]'\nset offsets graph 0.03, graph 0.03, 0, 0\nset key top left\nset ylabel 'M [kg]'\n"
       << "set title 'M: base (solid) and new (dashed), 95% intervals'\nplot " << mPlot.str() << "\n"
       << "set ylabel 'dM [kg]'\nset title 'dM = M(new) - M(base), 95% interval'\nset xzeroaxis\nplot " << dPlot.str() << "\nunset multiplot\n";
    std::string warning;
    const auto png = renderPng(dir, "report", "pngcairo size 1200,500 noenhanced", gp.str(), warning);
    return {{"points", points},
            {"table", (dir / "report.md").string()},
            {"csv", (dir / "report.csv").string()},
            {"plot", png ? nlohmann::json(png->string()) : nlohmann::json()},
            {"plot_warning", warning}};
}

}  // namespace mixload::experiments
