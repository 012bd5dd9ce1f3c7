// SPDX-License-Identifier: GPL-3.0-or-later
#include "studies/fidelity_pilot.hpp"

#include <cmath>
#include <map>
#include <sstream>

#include "campaign/campaign.hpp"
#include "cases/meshed_geometry.hpp"
#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "store/ledger.hpp"

namespace mixload::experiments {

namespace {
constexpr double kFidelityScatter = 0.1;  // largest log-space residual scatter that earns co-kriging its place
}  // namespace

namespace {

struct Side {
    double m = 0, core = 0;
};

// A campaign's finished steady points, keyed by "point <index>" when the two campaigns share their
// design (the same inputs at every index: `campaign create` with the same ranges, design, n and seed
// on two meshes); a point whose inputs differ from the other side's is not a pair.
std::map<std::string, std::pair<Side, nlohmann::json>> campaignRuns(const std::filesystem::path& dir) {
    const store::Ledger ledger(dir / "ledger.sqlite");
    const std::string name = dir.filename().string();
    if (!ledger.campaign(name)) throw InputError("study", dir.string(), "a campaign directory <dir>/NAME with NAME's ledger");
    std::map<std::string, std::pair<Side, nlohmann::json>> out;
    for (const auto& r : ledger.runs(name)) {
        if (r.status != "done" || !r.result.value("steady", false) || !r.result.contains("loading_kg")) continue;
        auto inputs = r.params;
        inputs.erase("scene_hash");
        out["point " + std::to_string(r.index)] = {{r.result["loading_kg"].get<double>(), r.coreSeconds.value_or(0.0)},
                                                   inputs};
    }
    return out;
}

// variant -> loading and cost, for the runs with a steady verdict ("reference" for the reference).
std::map<std::string, Side> studyRuns(const std::filesystem::path& dir) {
    const auto file = dir / "study.json";
    if (!std::filesystem::is_regular_file(file))
        throw InputError("study", dir.string(),
                         "a directory with a formulation study's study.json, or a campaign directory with its ledger");
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(readFile(file));
    } catch (const std::exception& e) {
        throw InputError("study", file.string(), std::string("valid JSON (") + e.what() + ")");
    }
    std::map<std::string, Side> out;
    const auto take = [&](const std::string& name, const nlohmann::json& r) {
        if (r.is_object() && r.value("steady", false) && r.contains("loading_kg"))
            out[name] = {r["loading_kg"].get<double>(), r.value("core_seconds", 0.0)};
    };
    take("reference", j.value("reference", nlohmann::json()));
    for (const auto& r : j.value("rows", nlohmann::json::array())) take(r.value("variant", std::string()), r);
    return out;
}

// Two mixer campaigns are paired only if their meshes cut one impeller (a collapse has none).
void requireSameCampaignImpeller(const std::filesystem::path& fine, const std::filesystem::path& coarse) {
    const auto info = [](const std::filesystem::path& dir) { return store::Ledger(dir / "ledger.sqlite").campaign(dir.filename().string()); };
    const auto a = info(fine), b = info(coarse);
    if (!a || !b || a->scene != "mixer" || b->scene != "mixer") return;  // campaignRuns names the missing ledger
    cases::requireSameImpeller(mixerSceneFor(a->sceneJson, nlohmann::json::object()),
                               mixerSceneFor(b->sceneJson, nlohmann::json::object()), "coarse", coarse.string());
}

// The impeller a formulation study's reference run simulated (what its mesh cut), which studies
// record since issue 65; older studies compared meshes that cut different paddles, unseen.
nlohmann::json studyImpeller(const std::filesystem::path& dir) {
    const auto j = nlohmann::json::parse(readFile(dir / "study.json"));
    const auto ref = j.value("reference", nlohmann::json::object());
    if (!ref.is_object() || !ref.contains("impeller"))
        throw InputError("study", dir.string(),
                         "a study whose runs record the impeller they simulated (reference.impeller, written since "
                         "issue 65): without it the two meshes may have cut different paddles");
    return ref["impeller"];
}

void requireSameStudyImpeller(const std::filesystem::path& fine, const std::filesystem::path& coarse) {
    const auto a = studyImpeller(fine), b = studyImpeller(coarse);
    for (const char* k : {"paddle_thickness_m", "paddle_width_m", "paddle_radial_m"}) {
        const double x = a.value(k, 0.0), y = b.value(k, 0.0);
        if (!(std::abs(x - y) <= cases::kGeometryTolerance * std::max(x, y)))
            throw InputError("coarse", coarse.string(),
                             "a study of the same impeller as " + fine.string() + " (" + k + " " + formatNumber(x) +
                                 " there, " + formatNumber(y) + " here: another impeller, not another resolution)");
    }
}

bool isCampaign(const std::filesystem::path& dir) { return std::filesystem::is_regular_file(dir / "ledger.sqlite"); }

// Both sides' steady runs, keyed so that equal keys are a pair.
std::pair<std::map<std::string, Side>, std::map<std::string, Side>> pairable(const std::filesystem::path& fine,
                                                                             const std::filesystem::path& coarse) {
    if (isCampaign(fine) != isCampaign(coarse))
        throw InputError("study", coarse.string(), std::string("the same kind as ") + fine.string() +
                                                       " (two formulation studies or two campaigns)");
    if (!isCampaign(fine)) {
        auto f = studyRuns(fine), c = studyRuns(coarse);
        requireSameStudyImpeller(fine, coarse);
        return {f, c};
    }
    auto f = campaignRuns(fine), c = campaignRuns(coarse);
    requireSameCampaignImpeller(fine, coarse);
    std::map<std::string, Side> fs, cs;
    for (const auto& [k, v] : f)
        if (const auto it = c.find(k); it != c.end() && it->second.second == v.second) {
            fs[k] = v.first;
            cs[k] = it->second.first;
        }
    return {fs, cs};
}

}  // namespace

nlohmann::json fidelityPilot(const std::filesystem::path& fine, const std::filesystem::path& coarse, const std::filesystem::path& out) {
    const auto [f, c] = pairable(fine, coarse);
    std::vector<std::string> names;
    std::vector<double> xf, xc;
    double coreF = 0, coreC = 0;
    for (const auto& [name, s] : f) {
        const auto it = c.find(name);
        if (it == c.end()) continue;
        names.push_back(name);
        xf.push_back(s.m);
        xc.push_back(it->second.m);
        coreF += s.core, coreC += it->second.core;
    }
    const auto n = static_cast<double>(names.size());
    nlohmann::json r{{"fine", fine.string()}, {"coarse", coarse.string()}, {"pairs", names.size()}};
    nlohmann::json pairs = nlohmann::json::array();
    for (size_t i = 0; i < names.size(); ++i) pairs.push_back({{"variant", names[i]}, {"fine_kg", xf[i]}, {"coarse_kg", xc[i]}, {"ratio", xf[i] / xc[i]}});
    r["pairs_list"] = pairs;
    if (names.size() >= 3) {
        double mx = 0, my = 0;
        for (size_t i = 0; i < names.size(); ++i) mx += xc[i] / n, my += xf[i] / n;
        double sxx = 0, sxy = 0, syy = 0;
        for (size_t i = 0; i < names.size(); ++i) sxx += (xc[i] - mx) * (xc[i] - mx), sxy += (xc[i] - mx) * (xf[i] - my), syy += (xf[i] - my) * (xf[i] - my);
        const double a = sxy / sxx, b = my - a * mx, r2 = sxx > 0 && syy > 0 ? sxy * sxy / (sxx * syy) : 0;
        double rm = 0, rs = 0;
        for (size_t i = 0; i < names.size(); ++i) rm += xf[i] / xc[i] / n;
        for (size_t i = 0; i < names.size(); ++i) rs += std::pow(xf[i] / xc[i] - rm, 2) / std::max(n - 1, 1.0);
        r["fit"] = {{"slope", a}, {"intercept_kg", b}, {"r2", r2}};
        r["ratio"] = {{"mean", rm}, {"std", std::sqrt(rs)}};
        // The surrogates model log M, so what a coarse run can carry is judged there: r^2 of
        // ln M_fine on ln M_coarse, and the scatter of its residuals (a relative error of M). On M
        // itself r^2 is carried by the largest loadings: v2's first 7 pairs gave 0.97 on M with a
        // 0.30 scatter in log (thin films 2-3 times heavier on 1 cm).
        double lx = 0, ly = 0;
        for (size_t i = 0; i < names.size(); ++i) lx += std::log(xc[i]) / n, ly += std::log(xf[i]) / n;
        double lxx = 0, lxy = 0, lyy = 0;
        for (size_t i = 0; i < names.size(); ++i) {
            const double u = std::log(xc[i]) - lx, v = std::log(xf[i]) - ly;
            lxx += u * u, lxy += u * v, lyy += v * v;
        }
        const double la = lxx > 0 ? lxy / lxx : 0, lr2 = lxx > 0 && lyy > 0 ? lxy * lxy / (lxx * lyy) : 0;
        const double scatter = std::sqrt(std::max(lyy - la * lxy, 0.0) / std::max(n - 2, 1.0));
        r["log_fit"] = {{"slope", la}, {"intercept", ly - la * lx}, {"r2", lr2}, {"residual_scatter", scatter}};
        // A scatter of 10% leaves a fine run's loading predicted from its coarse twin three times
        // the surrogates' 3% target, which the fine runs' own discrepancy model can still close;
        // beyond it the coarse runs carry too little of the fine answer to earn their cost.
        if (!std::isfinite(scatter)) r["verdict"] = "skip (a loading of zero or less: no log-space fit)";
        else if (names.size() < 8) r["verdict"] = "pilot too small (fewer than 8 pairs)";
        else if (lr2 >= 0.9 && scatter <= kFidelityScatter) r["verdict"] = "earns its place (log-space r^2 >= 0.9, scatter <= 10%)";
        else r["verdict"] = "skip (log-space r^2 " + formatNumber(lr2) + ", scatter " + formatNumber(scatter) + "; needs r^2 >= 0.9 and scatter <= 0.1)";
    } else {
        r["verdict"] = "pilot too small (fewer than 8 pairs)";
    }
    if (coreC > 0) r["cost_ratio"] = coreF / coreC;

    std::ostringstream md, csv, dat;
    md << "Multi-fidelity pilot: `" << fine.string() << "` (fine) against `" << coarse.string() << "` (coarse), runs steady in both.\n\n"
       << "| variant | fine M [kg] | coarse M [kg] | fine / coarse |\n|---|---|---|---|\n";
    csv << "variant,fine_kg,coarse_kg,ratio\n";
    for (size_t i = 0; i < names.size(); ++i) {
        md << "| " << names[i] << " | " << formatNumber(xf[i]) << " | " << formatNumber(xc[i]) << " | " << formatNumber(xf[i] / xc[i]) << " |\n";
        csv << names[i] << ',' << xf[i] << ',' << xc[i] << ',' << xf[i] / xc[i] << '\n';
        dat << xc[i] << ' ' << xf[i] << '\n';
    }
    if (r.contains("fit"))
        md << "\nFit: M_fine = " << formatNumber(r["fit"]["slope"].get<double>()) << " M_coarse + " << formatNumber(r["fit"]["intercept_kg"].get<double>())
           << " kg, r² = " << formatNumber(r["fit"]["r2"].get<double>()) << "; ratio " << formatNumber(r["ratio"]["mean"].get<double>()) << " ± "
           << formatNumber(r["ratio"]["std"].get<double>()) << ".\n"
           << "In log space: ln M_fine = " << formatNumber(r["log_fit"]["slope"].get<double>()) << " ln M_coarse + const, r² = "
           << formatNumber(r["log_fit"]["r2"].get<double>()) << ", residual scatter " << formatNumber(r["log_fit"]["residual_scatter"].get<double>())
           << ".\n";
    md << "\nVerdict: " << r["verdict"].get<std::string>() << ".\n";
    std::filesystem::create_directories(out);
    writeFileAtomic(out / "fidelity.md", md.str());
    writeFileAtomic(out / "fidelity.csv", csv.str());
    writeFileAtomic(out / "fidelity.dat", dat.str());
    std::ostringstream gp;
    // Log axes: the verdict is judged on ln M, and the thin films a linear plot crowds into a corner
    // are where the meshes disagree.
    gp << "set title 'fine against coarse mesh, " << names.size()
       << " pairs'\nset xlabel 'M, coarse mesh [kg]'\nset ylabel 'M, fine mesh [kg]'\nset key top left Left reverse\nset grid\n"
       << "set logscale xy\nplot 'fidelity.dat' using 1:2 with points pt 7 ps 1.5 title 'steady in both'";
    if (r.contains("log_fit"))
        gp << ", exp(" << r["log_fit"]["intercept"].get<double>() << ")*x**" << r["log_fit"]["slope"].get<double>()
           << " lw 2 title sprintf('log-space fit: r2 %.2f, scatter %.2f', " << r["log_fit"]["r2"].get<double>() << ", "
           << r["log_fit"]["residual_scatter"].get<double>() << "), x dt 2 lc rgb 'gray' title 'equal'";
    gp << "\n";
    std::string warning;
    const auto png = renderPng(out, "fidelity", "pngcairo size 700,600 noenhanced", gp.str(), warning);
    r["table"] = (out / "fidelity.md").string();
    r["plot"] = png ? nlohmann::json(png->string()) : nlohmann::json();
    return r;
}

}  // namespace mixload::experiments
