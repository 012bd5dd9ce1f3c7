// SPDX-License-Identifier: GPL-3.0-or-later
#include "studies/formulation_study.hpp"

#include <cmath>
#include <cstdio>
#include <iterator>
#include <sstream>
#include <utility>

#include "common/atomic_file.hpp"
#include "common/gnuplot.hpp"
#include "common/input_error.hpp"
#include "campaign/campaign_table.hpp"
#include "run/mixer_job.hpp"
#include "studies/mixer_study.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {

const char* kKeys[] = {"mu_s", "mu_d", "i0", "d", "rho"};

bool knownKey(const std::string& k) {
    for (const char* n : kKeys)
        if (k == n) return true;
    return false;
}

std::string pct(double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%+.1f%%", 100 * v);
    return b;
}

std::string describe(const FormulationVariant& v) {
    std::ostringstream os;
    bool first = true;
    for (const auto& [k, f] : v.factors) {
        os << (first ? "" : ", ") << k << " " << pct(f - 1);
        first = false;
    }
    return os.str();
}

// The paper's Fig. 7: M rises with each parameter but I0.
int paperSign(const std::string& k) { return k == "i0" ? -1 : +1; }

// Least-squares line y = intercept + slope x: {slope, intercept}.
std::pair<double, double> fitLine(const std::vector<std::pair<double, double>>& pts) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const auto& [x, y] : pts) sx += x, sy += y, sxx += x * x, sxy += x * y;
    const double n = static_cast<double>(pts.size());
    const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    return {slope, (sy - slope * sx) / n};
}

std::string signVerdict(double slope, int sign) {
    return sign == 0 ? "no expectation" : (slope > 0 ? 1 : -1) == sign ? "same sign" : "opposite sign";
}

}  // namespace

std::vector<FormulationVariant> formulationPreset(const std::string& name) {
    std::vector<FormulationVariant> out;
    if (name == "paper-whatifs" || name == "all") {
        // Biroun et al. (2023), Fig. 8: +50% bulk density with -10% and with -32% mu_s.
        out.push_back({"whatif-rho+50-mus-10", {{"rho", 1.5}, {"mu_s", 0.9}}, 0.25, +1});
        out.push_back({"whatif-rho+50-mus-32", {{"rho", 1.5}, {"mu_s", 0.68}}, -0.08, -1});
    }
    if (name == "fig7-signs" || name == "all" || name == "fig7" || name == "fig7-similar") {
        // Its Fig. 7: M rises with mu_s, mu_d, d and rho, falls with I0. fig7 runs six factors per
        // parameter, as the paper does; fig7-signs the two at +-20% (the same runs); fig7-similar
        // the six without I0's, whose panel the d runs give (fig7Fit).
        const bool six = name == "fig7" || name == "fig7-similar";
        const std::vector<int> steps = six ? std::vector<int>{-30, -20, -10, 10, 20, 30} : std::vector<int>{-20, 20};
        for (const char* k : kKeys) {
            if (name == "fig7-similar" && std::string(k) == "i0") continue;
            const int sign = paperSign(k);
            for (int p : steps)
                out.push_back({std::string(k) + (p > 0 ? "+" : "") + std::to_string(p), {{k, 1 + p / 100.0}}, std::nullopt,
                               p > 0 ? sign : -sign});
        }
    }
    if (out.empty()) throw InputError("preset", name, "paper-whatifs | fig7-signs | fig7 | fig7-similar | all");
    return out;
}

std::vector<FormulationVariant> formulationPreset(const std::string& name, const scene::MixerScene& reference,
                                                  std::vector<std::pair<std::string, std::string>>& skipped) {
    std::vector<FormulationVariant> out;
    for (auto& v : formulationPreset(name)) try {
            applyVariant(reference, v);
            out.push_back(std::move(v));
        } catch (const InputError& e) {
            skipped.push_back({v.name, e.what()});
        }
    return out;
}

FormulationVariant parseFormulationVariant(const std::string& text) {
    const auto colon = text.find(':');
    if (colon == std::string::npos || colon == 0)
        throw InputError("variant", text, "NAME:KEY=FACTOR[,KEY=FACTOR...] with KEY mu_s|mu_d|i0|d|rho");
    FormulationVariant v;
    v.name = text.substr(0, colon);
    std::stringstream ss(text.substr(colon + 1));
    for (std::string item; std::getline(ss, item, ',');) {
        const auto eq = item.find('=');
        const std::string key = item.substr(0, eq);
        const auto f = eq == std::string::npos ? std::nullopt : parseNumber(item.substr(eq + 1));
        if (!knownKey(key)) throw InputError("variant " + v.name, key, "mu_s | mu_d | i0 | d | rho");
        if (!f || !(*f > 0) || !std::isfinite(*f))
            throw InputError("variant " + v.name + " " + key, item, "a factor > 0, e.g. rho=1.5");
        v.factors[key] = *f;
    }
    if (v.factors.empty()) throw InputError("variant", text, "at least one KEY=FACTOR");
    return v;
}

scene::MixerScene applyVariant(scene::MixerScene s, const FormulationVariant& v) {
    auto& m = s.material;
    for (const auto& [k, f] : v.factors) {
        if (k == "mu_s") m.muS *= f;
        else if (k == "mu_d") m.muD *= f;
        else if (k == "i0") m.I0 *= f;
        else if (k == "d") m.grainDiameter *= f;
        else if (k == "rho") m.grainDensity *= f;  // the bulk density follows (phi fixed)
    }
    m.name += "-" + v.name;
    try {
        s.validate();
    } catch (const InputError& e) {
        throw InputError("variant " + v.name + " (" + describe(v) + "): " + e.what());
    }
    return s;
}

nlohmann::json fig7Fit(const nlohmann::json& rows) {
    nlohmann::json params = nlohmann::json::array();
    for (const char* k : kKeys) {
        std::vector<std::pair<double, double>> pts{{1.0, 1.0}};
        int sign = 0;
        for (const auto& r : rows) {
            if (r["factors"].size() != 1 || !r["factors"].contains(k)) continue;
            const double f = r["factors"][k].get<double>();
            sign = (f > 1 ? 1 : -1) * r["sign_paper"].get<int>();
            if (!r.contains("change_model")) continue;  // not steady: no point
            pts.push_back({f, 1 + r["change_model"].get<double>()});
        }
        if (pts.size() < 2) continue;
        const auto [slope, icpt] = fitLine(pts);
        params.push_back({{"parameter", k}, {"steady_runs", pts.size() - 1}, {"slope", slope}, {"intercept", icpt},
                          {"sign_paper", sign}, {"verdict", signVerdict(slope, sign)}, {"points", pts}});
    }
    // mu(I) sees d and I0 only through d/I0 (measured on the calibrated scene: both x2 moved M by
    // -0.08%), so I0 x f is d x 1/f: without runs of its own, I0's panel is the d runs mirrored.
    bool hasI0 = false;
    size_t d = params.size();
    for (size_t i = 0; i < params.size(); ++i) {
        hasI0 = hasI0 || params[i]["parameter"] == "i0";
        if (params[i]["parameter"] == "d") d = i;
    }
    if (hasI0 || d == params.size()) return params;
    std::vector<std::pair<double, double>> pts;
    for (const auto& xy : params[d]["points"]) pts.push_back({1 / xy[0].get<double>(), xy[1].get<double>()});
    const auto [slope, icpt] = fitLine(pts);
    nlohmann::json i0{{"parameter", "i0"}, {"steady_runs", params[d]["steady_runs"]}, {"slope", slope}, {"intercept", icpt},
                      {"sign_paper", paperSign("i0")}, {"verdict", signVerdict(slope, paperSign("i0"))}, {"points", pts},
                      {"from", "the d runs, I0 x f = d x 1/f (d/I0 similarity)"}};
    params.insert(params.begin() + static_cast<std::ptrdiff_t>(d), i0);  // in kKeys' order, before d
    return params;
}

nlohmann::json fig7ModelCurves(const surrogates::Surrogate& model, const scene::MixerScene& reference) {
    auto ws = model.makeWorkspace();
    const double m0 = model.predict(sceneInputs(reference), ws).m;
    nlohmann::json params = nlohmann::json::array();
    for (const char* k : kKeys) {
        std::vector<std::pair<double, double>> pts;
        std::vector<double> outside;
        nlohmann::json row{{"parameter", k}, {"sign_paper", paperSign(k)}};
        for (int step = 70; step <= 130; ++step) {
            const double f = step / 100.0;
            scene::MixerScene s;
            try {
                s = applyVariant(reference, {k, {{k, f}}, std::nullopt, 0});
            } catch (const InputError&) {
                continue;  // e.g. mu_d scaled below mu_s
            }
            const auto p = model.predict(sceneInputs(s), ws);
            pts.push_back({f, p.m / m0});
            if (!p.inBox) outside.push_back(f);
            if (step == 80) row["at_0.8"] = p.m / m0;
            if (step == 120) row["at_1.2"] = p.m / m0;
        }
        if (pts.size() < 2) continue;
        const auto [slope, icpt] = fitLine(pts);
        row["slope"] = slope;
        row["intercept"] = icpt;
        row["verdict"] = signVerdict(slope, paperSign(k));
        row["outside_training_box"] = outside;
        row["points"] = pts;
        params.push_back(row);
    }
    return {{"reference_kg", m0}, {"source", model.sourceLabel()}, {"parameters", params}};
}

namespace {

// The paper's Fig. 7 from the study's one-parameter variants: per parameter, M / M_reference
// against the parameter / its reference value (the reference as the point (1, 1)), a least-squares
// line through the points, its slope (the elasticity of M) and its sign against the paper's; with
// a model, its curves (dashed) beside them. m0 is NaN while the reference has no steady verdict.
nlohmann::json writeFig7(const fs::path& out, const nlohmann::json& rows, double m0, const nlohmann::json& model) {
    const nlohmann::json params = std::isnan(m0) ? nlohmann::json::array() : fig7Fit(rows);
    nlohmann::json j{{"parameters", params}, {"reference_loading_kg", std::isnan(m0) ? nlohmann::json() : nlohmann::json(m0)}};
    if (!model.is_null()) j["model"] = model;
    if (params.empty() && model.is_null()) return j;
    const auto entry = [](const nlohmann::json& list, const std::string& k) -> const nlohmann::json* {
        for (const auto& p : list)
            if (p["parameter"] == k) return &p;
        return nullptr;
    };
    const auto num = [](double v) { return formatNumber(std::round(v * 1000) / 1000); };
    std::ostringstream md, csv, dat, mdat, gp;
    md << "| parameter | steady full runs | slope d(M/M0)/d(x/x0), full runs | slope, model | model M/M0 at x0.8, x1.2 "
          "| paper | full runs against the paper | model against the paper |\n|---|---|---|---|---|---|---|---|\n";
    csv << "parameter,factor,m_over_m0,source\n";
    gp << "set terminal pngcairo size 900,600 noenhanced\nset output 'fig7.png'\nset grid\nset key top left\n"
       << "set xlabel 'parameter / its reference value'\nset ylabel 'M / M_reference'\n"
       << "set title 'Fig. 7 on the calibrated scene: full runs (points, fitted line)"
       << (model.is_null() ? "" : ", surrogate (dashed)") << "'\nplot ";
    int runBlock = 0, modelBlock = 0;
    bool firstPlot = true;
    std::vector<std::string> outsideNotes;
    for (size_t b = 0; b < std::size(kKeys); ++b) {
        const std::string k = kKeys[b];
        const nlohmann::json* p = entry(params, k);
        const nlohmann::json* q = model.is_null() ? nullptr : entry(model["parameters"], k);
        if (!p && !q) continue;
        const int sign = paperSign(k);
        md << "| " << k << (p && p->contains("from") ? " (from the d runs)" : "") << " | " << (p ? (*p)["steady_runs"].get<int>() : 0) << " | " << (p ? num((*p)["slope"]) : "-") << " | "
           << (q ? num((*q)["slope"]) : "-") << " | "
           << (q && q->contains("at_0.8") && q->contains("at_1.2") ? num((*q)["at_0.8"]) + ", " + num((*q)["at_1.2"]) : "-")
           << " | " << (sign > 0 ? "rises" : "falls") << " | " << (p ? (*p)["verdict"].get<std::string>() : "-") << " | "
           << (q ? (*q)["verdict"].get<std::string>() : "-") << " |\n";
        const auto sep = [&] { return std::exchange(firstPlot, false) ? "" : ", "; };
        if (p) {
            for (const auto& xy : (*p)["points"]) {
                csv << k << ',' << xy[0] << ',' << xy[1] << ",full run\n";
                dat << xy[0] << ' ' << xy[1] << '\n';
            }
            dat << "\n\n";
            gp << sep() << "'fig7.dat' index " << runBlock++ << " with points pt " << 5 + 2 * b << " ps 1.5 lc " << b + 1
               << " title '" << k << (p->contains("from") ? " (d runs)" : "") << "', " << (*p)["intercept"].get<double>() << " + " << (*p)["slope"].get<double>()
               << " * x with lines lc " << b + 1 << " notitle";
        }
        if (q) {
            for (const auto& xy : (*q)["points"]) {
                csv << k << ',' << xy[0] << ',' << xy[1] << ",model\n";
                mdat << xy[0] << ' ' << xy[1] << '\n';
            }
            mdat << "\n\n";
            gp << sep() << "'fig7-model.dat' index " << modelBlock++ << " with lines dt 2 lw 2 lc " << b + 1 << " title '" << k
               << ", model'";
            if (!(*q)["outside_training_box"].empty())
                outsideNotes.push_back(k + " at x" + num((*q)["outside_training_box"].front()) + "..x" +
                                       num((*q)["outside_training_box"].back()));
        }
    }
    md << "\n";
    if (!std::isnan(m0))
        md << "M0 = " << m0 << " kg (the reference's full run). A parameter's line is fitted through the reference and its "
              "steady variants. ";
    if (!model.is_null()) {
        md << "The model (" << model["source"].get<std::string>() << ") is drawn over its own M at the reference, "
           << formatNumber(model["reference_kg"].get<double>()) << " kg, with each parameter alone scaled by 0.7-1.3";
        if (!outsideNotes.empty()) {
            md << "; it leaves its training box for";
            for (const auto& n : outsideNotes) md << ' ' << n << (&n == &outsideNotes.back() ? "" : ",");
        }
        md << ". ";
    }
    md << "The paper's Fig. 7 has M rising with mu_s, mu_d, d and rho and falling with I0.\n";
    writeFileAtomic(out / "fig7.md", md.str());
    writeFileAtomic(out / "fig7.csv", csv.str());
    writeFileAtomic(out / "fig7.dat", dat.str());
    writeFileAtomic(out / "fig7-model.dat", mdat.str());
    gp << '\n';
    const std::string warn = runGnuplot(out, "fig7.gp", gp.str());
    j["table_md"] = (out / "fig7.md").string();
    j["plot"] = warn.empty() ? (out / "fig7.png").string() : "";
    if (!warn.empty()) j["plot_warning"] = warn;
    return j;
}

}  // namespace

nlohmann::json runFormulationStudy(const FormulationStudy& study) {
    // Every scene is valid before the first run starts.
    std::vector<scene::MixerScene> scenes{study.reference};
    for (const auto& v : study.variants) scenes.push_back(applyVariant(study.reference, v));
    if (!study.warmFrom.empty()) run::warmSourceTime(study.warmFrom);
    fs::create_directories(study.out);
    const auto results = runMixerScenes(scenes, study.runs.empty() ? study.out / "runs" : study.runs, study.jobs,
                                        study.np, study.progress, "formulation study",
                                        study.warmFrom.empty() ? std::vector<fs::path>{}
                                                               : std::vector<fs::path>(scenes.size(), study.warmFrom),
                                        study.deadline);
    const auto& ref = results[0];
    const bool refOk = ref.contains("loading_kg") && ref.value("steady", false);
    const double m0 = ref.value("loading_kg", NAN);
    // A change smaller than the steady test's tolerance (either run's) cannot carry a sign.
    const double noise = 2 * study.reference.steadyTol;
    nlohmann::json rows = nlohmann::json::array();
    std::ostringstream md, csv, dat;
    md << "Reference: " << study.reference.material.name << ", " << study.reference.rpm << " rpm, "
       << study.reference.feedKgH << " kg/h, scene " << study.reference.name << " (" << study.reference.hash()
       << (study.warmFrom.empty() ? std::string() : ", every run started from " + study.warmFrom.string())
       << "): M = " << (ref.contains("loading_kg") ? std::to_string(m0) + " kg"
                        : ref.contains("stopped")   ? "not finished (" + ref["stopped"].get<std::string>() + ")"
                                                    : std::string("failed"))
       << (refOk ? "" : " (NOT steady: no verdicts)") << "\n\n"
       << "| variant | change | M [kg] | dM model | dM paper | verdict |\n|---|---|---|---|---|---|\n";
    csv << "variant,change,loading_kg,steady,change_model,change_paper,sign_paper,verdict,run_dir\n";
    int pass = 0, fail = 0, open = 0;
    for (size_t i = 0; i < study.variants.size(); ++i) {
        const auto& v = study.variants[i];
        const auto& r = results[i + 1];
        nlohmann::json row{{"variant", v.name}, {"change", describe(v)}, {"factors", v.factors}};
        for (auto it = r.begin(); it != r.end(); ++it)
            if (it.key() != "history") row[it.key()] = it.value();
        std::string verdict;
        double dm = NAN;
        if (r.contains("stopped")) verdict = "open: not finished (" + r["stopped"].get<std::string>() + ")";
        else if (!r.contains("loading_kg")) verdict = "run failed";
        else if (!r.value("steady", false) || !refOk) verdict = "open: not steady";
        else {
            dm = r["loading_kg"].get<double>() / m0 - 1;
            row["change_model"] = dm;
            const int expected = v.paperChange ? (*v.paperChange > 0 ? 1 : -1) : v.paperSign;
            if (expected == 0) verdict = "no expectation";
            else if (std::abs(dm) <= noise) verdict = "fail: no change beyond the steady tolerance";
            else if ((dm > 0 ? 1 : -1) != expected) verdict = "fail: opposite sign";
            else if (v.paperChange && std::abs((1 + dm) / (1 + *v.paperChange) - 1) > 0.12)
                verdict = "fail: right sign, off by more than the paper's 12% band";
            else verdict = "pass";
        }
        if (verdict == "pass") ++pass;
        else if (verdict.rfind("fail", 0) == 0) ++fail;
        else ++open;
        row["verdict"] = verdict;
        if (v.paperChange) row["change_paper"] = *v.paperChange;
        row["sign_paper"] = v.paperChange ? (*v.paperChange > 0 ? 1 : -1) : v.paperSign;
        const std::string paper = v.paperChange ? pct(*v.paperChange)
                                  : v.paperSign > 0 ? "rises" : v.paperSign < 0 ? "falls" : "-";
        md << "| " << v.name << " | " << describe(v) << " | "
           << (r.contains("loading_kg") ? std::to_string(r["loading_kg"].get<double>()) : "-")
           << (r.value("steady", false) ? "" : " (not steady)") << " | " << (std::isnan(dm) ? "-" : pct(dm)) << " | "
           << paper << " | " << verdict << " |\n";
        csv << v.name << ",\"" << describe(v) << "\"," << r.value("loading_kg", NAN) << ','
            << (r.value("steady", false) ? "yes" : "no") << ',' << dm << ','
            << (v.paperChange ? std::to_string(*v.paperChange) : "") << ',' << row["sign_paper"] << ",\"" << verdict
            << "\"," << r.value("run_dir", std::string()) << '\n';
        // Bar chart data: the paper's number where it gives one, else its sign as +-5%.
        dat << i << " \"" << v.name << "\" " << (std::isnan(dm) ? 0.0 : 100 * dm) << ' '
            << (v.paperChange ? 100 * *v.paperChange : 5.0 * row["sign_paper"].get<int>()) << '\n';
        rows.push_back(row);
    }
    md << "\n" << pass << " pass, " << fail << " fail, " << open
       << " open. A change within twice the steady tolerance (" << pct(noise).substr(1)
       << ") carries no sign; a what-if passes when M_variant/M_reference is within the paper's 12% band of its "
          "ratio. Where the paper gives only a trend (Fig. 7) the bar shows its sign as +-5%.\n";
    if (!study.skipped.empty()) md << "\nNot run (the preset's factor leaves the valid range at this reference):\n";
    nlohmann::json skipped = nlohmann::json::array();
    for (const auto& [name, why] : study.skipped) {
        md << "- " << name << ": " << why << "\n";
        skipped.push_back({{"variant", name}, {"reason", why}});
    }
    writeFileAtomic(study.out / "formulation.dat", dat.str());
    std::ostringstream gp;
    gp << "set terminal pngcairo size 1100,520 noenhanced\nset output 'formulation.png'\n"
       << "set style data histograms\nset style histogram clustered gap 1\nset style fill solid 0.8 border -1\n"
       << "set xtics rotate by -35\nset ylabel 'change of M against the reference [%]'\nset grid ytics\n"
       << "set title 'formulation changes: mixload (full runs) against the paper'\n"
       << "plot 'formulation.dat' using 3:xtic(2) title 'mixload', '' using 4 title 'paper (trend only: sign)'\n";
    const std::string warn = runGnuplot(study.out, "formulation.gp", gp.str());
    writeFileAtomic(study.out / "table.md", md.str());
    writeFileAtomic(study.out / "table.csv", csv.str());
    size_t unfinished = ref.contains("stopped");
    for (const auto& r : rows) unfinished += r.contains("stopped");
    nlohmann::json result{{"reference", {{"scene_hash", study.reference.hash()}}},
                          {"unfinished", unfinished},
                          {"stopped_at_max_hours", unfinished > 0},
                          {"warm_from", study.warmFrom.empty() ? nlohmann::json() : nlohmann::json(study.warmFrom.string())},
                          {"rows", rows},
                          {"skipped", skipped},
                          {"pass", pass},
                          {"fail", fail},
                          {"open", open},
                          {"table_md", (study.out / "table.md").string()},
                          {"plot", warn.empty() ? (study.out / "formulation.png").string() : ""}};
    for (auto it = ref.begin(); it != ref.end(); ++it)
        if (it.key() != "history") result["reference"][it.key()] = it.value();
    if (!warn.empty()) result["plot_warning"] = warn;
    nlohmann::json model = study.model ? fig7ModelCurves(*study.model, study.reference) : nlohmann::json();
    if (!model.is_null()) model["path"] = study.modelPath;
    if (refOk || !model.is_null()) result["fig7"] = writeFig7(study.out, rows, refOk ? m0 : NAN, model);
    writeFileAtomic(study.out / "study.json", result.dump(2));
    return result;
}

}  // namespace mixload::experiments
