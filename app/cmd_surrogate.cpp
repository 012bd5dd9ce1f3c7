// SPDX-License-Identifier: GPL-3.0-or-later
// mixload surrogate fit|info and mixload check.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "campaign/campaign.hpp"
#include "campaign/campaign_table.hpp"
#include "app/commands.hpp"
#include "app/point_options.hpp"
#include "check.hpp"
#include "check_plot.hpp"
#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "mixload_version.hpp"
#include "learning_curve.hpp"
#include "model.hpp"
#include "run/label_protocol.hpp"

namespace mixload::app {

namespace {

struct SurrogateCmd {
    std::string campaign, dir = "runs/campaigns", table, kind = "kriging", output, model, transform = "auto",
                kernel = "matern52", trend = "constant", objective = "likelihood", holdoutCampaign, holdoutTable,
                twoStates = "protocol";
    int holdout = 0, starts = 20;
    std::vector<int> sizes;
    std::vector<std::string> trendInputs;
    double target = 0.03, noise = 0;
    std::string out = "runs/surrogates/curve", plot;
    unsigned seed = 1;
    bool noSelect = false, json = false, noRecord = false, similarity = false, listRuns = false;
    std::optional<double> threshold;
};

// Training or checking data: a campaign's ledger or a CSV table, exactly one of them.
// A point whose replicate sits in another steady state is labelled as --two-states says, and
// source["two_states"] lists what was done.
surrogates::Table loadRuns(const SurrogateCmd& o, nlohmann::json& source) {
    if (o.campaign.empty() == o.table.empty())
        throw InputError("--campaign / --table", "(both or neither)", "exactly one of them");
    const auto policy = surrogates::twoStatesFromString(o.twoStates);
    surrogates::Table t;
    if (!o.campaign.empty()) {
        t = experiments::campaignTable(o.campaign, o.dir, source);
    } else {
        t = surrogates::readTable(o.table);
        source = t.provenance;
        source["table"] = o.table;
    }
    const auto two = surrogates::resolveTwoStates(t, policy, run::kLabelDepositKg);
    if (!two.empty()) source["two_states"] = {{"policy", o.twoStates}, {"points", two}};
    return t;
}

std::string pct(const nlohmann::json& v) {
    if (v.is_null()) return "n/a";
    std::ostringstream os;
    os << std::fixed << std::setprecision(2) << 100 * v.get<double>() << "%";
    return os.str();
}

// A regime model's parts, one line each: what each learnt from and how well on its own regime.
void printParts(const nlohmann::json& parts) {
    for (const auto& p : parts) {
        const auto trend = p["trend_inputs"].get<std::string>();
        std::cout << "  " << p["regime"].get<std::string>() << " part: " << p["n_train"] << " runs ("
                  << p["trained_on"].get<std::string>() << "), " << p["transform"].get<std::string>()
                  << (trend.empty() ? "" : ", linear trend in " + trend) << "; leave-one-out on its regime's runs "
                  << pct(p["own_loo_mean_rel_error"]) << '\n';
    }
}

surrogates::FitOptions fitOptions(const SurrogateCmd& o) {
    surrogates::FitOptions f;
    f.kind = o.kind;
    f.transform = o.transform;
    f.similarity = o.similarity;
    requireRange("noise", o.noise, 0, 1);
    f.noise = o.noise;
    f.select = !o.noSelect;
    f.trendInputs = o.trendInputs;
    try {
        f.kriging.kernel = surrogates::kernelFromString(o.kernel == "se" ? "squared-exponential" : o.kernel);
        f.kriging.trend = surrogates::trendFromString(o.trend);
    } catch (const std::invalid_argument&) {
        throw InputError("kernel/trend", o.kernel + "/" + o.trend, "matern52|se and constant|linear");
    }
    requireRange("starts", o.starts, 1, 1000);
    if (o.objective != "likelihood" && o.objective != "loo")
        throw InputError("objective", o.objective, "likelihood or loo");
    f.kriging.objective = o.objective;
    f.kriging.starts = o.starts;
    f.kriging.seed = o.seed;
    return f;
}

int fit(const SurrogateCmd& o) {
    if (o.output.empty()) throw InputError("output", "(missing)", "-o MODEL.json");
    requireRange("holdout", o.holdout, 0, 1e6);
    const auto f = fitOptions(o);
    nlohmann::json source;
    auto runs = loadRuns(o, source);
    if (static_cast<size_t>(o.holdout) >= runs.rows.size())
        throw InputError("holdout", std::to_string(o.holdout),
                         "fewer than the " + std::to_string(runs.rows.size()) + " usable runs");
    // The last runs of the design are held out: a design's order is random, so they are a fair
    // sample, and `mixload check` has runs the model never saw.
    std::vector<surrogates::Row> train(runs.rows.begin(), runs.rows.end() - o.holdout);
    nlohmann::json held = nlohmann::json::array();
    for (auto it = runs.rows.end() - o.holdout; it != runs.rows.end(); ++it) held.push_back(it->id);
    nlohmann::json provenance{{"source", source},
                                    {"runs_usable", runs.rows.size()},
                                    {"runs_skipped", runs.skipped},
                                    {"holdout_ids", held},
                                    {"options", {{"kind", o.kind}, {"transform", o.transform}, {"similarity", o.similarity}, {"noise", o.noise}, {"select", !o.noSelect},
                                                 {"kernel", o.kernel}, {"trend", o.trend}, {"trend_inputs", o.trendInputs}, {"objective", o.objective}, {"starts", o.starts},
                                                 {"seed", o.seed}, {"two_states", o.twoStates}}},
                                    {"mixload_version", kVersion},
                                    {"git_commit", kGitCommit},
                                    {"created_utc", utcNow()},
                                    {"command", "mixload surrogate fit " + (o.campaign.empty() ? "--table " + o.table : "--campaign " + o.campaign) +
                                                    " --kind " + o.kind + " --holdout " + std::to_string(o.holdout) +
                                                    (o.similarity ? " --similarity" : "") + (o.noise > 0 ? " --noise " + formatNumber(o.noise) : "") +
                                                    " --two-states " + o.twoStates}};
    if (const auto base = experiments::campaignBaseScene(source.value("base", nlohmann::json()))) {
        provenance["full_barrel_m3"] = base->geometry.openVolume();
        provenance["cell_size_m"] = base->cellSize;  // a base that names a level ("coarse") means this
    }
    const auto t0 = std::chrono::steady_clock::now();
    auto model = surrogates::Surrogate::fit(train, f, provenance);
    const double seconds = secondsSince(t0);
    model.save(o.output);
    const auto& v = model.validation();
    nlohmann::json out{{"model", o.output},        {"kind", o.kind},      {"n_train", train.size()},
                       {"n_holdout", o.holdout},   {"transform", v["transform"]}, {"loo", v},
                       {"warnings", model.warnings()}, {"fit_seconds", seconds}};
    if (o.json) {
        std::cout << out.dump(2) << '\n';
        return 0;
    }
    std::cout << o.kind << " model of M on " << train.size() << " runs (" << o.holdout << " held out, "
              << runs.skipped << " not finished or not steady), " << v["transform"].get<std::string>() << "\n  leave-one-out: mean "
              << pct(v["mean_rel_error"]) << ", max " << pct(v["max_rel_error"]) << " relative error, 95% coverage "
              << pct(v["coverage95"]) << "\n  fitted in " << std::setprecision(3) << seconds << " s, written to " << o.output
              << '\n';
    if (source.contains("two_states"))
        for (const auto& p : source["two_states"]["points"]) {
            std::cout << "  two steady states at " << p["id"].get<std::string>() << " (" << formatNumber(p["rpm"].get<double>())
                      << " rpm, " << formatNumber(p["feed_kg_h"].get<double>()) << " kg/h): loadings";
            for (size_t k = 0; k < p["loadings_kg"].size(); ++k)
                std::cout << (k ? "," : "") << " " << formatNumber(p["loadings_kg"][k].get<double>()) << " kg (from "
                          << (p["deposits_kg"][k].is_null() ? std::string("a warm start") : formatNumber(p["deposits_kg"][k].get<double>()) + " kg") << ")";
            std::cout << "; " << (p["kept_kg"].is_null() ? std::string("left out") : "trained on " + formatNumber(p["kept_kg"].get<double>()) + " kg")
                      << " (--two-states " << o.twoStates << ")\n";
        }
    if (model.kind() == "regimes") printParts(v["parts"]);
    for (const auto& w : model.warnings()) std::cout << "  warning: " << w << '\n';
    return 0;
}

// Error against training runs: the model refitted on the first n training runs for each n, checked
// on a fixed hold-out: the design's last --holdout runs, or another campaign's or table's runs (a
// hold-out placed by a design of its own, as issue 16 asks), never both.
int curve(const SurrogateCmd& o) {
    const auto f = fitOptions(o);
    nlohmann::json source, heldSource;
    const auto runs = loadRuns(o, source);
    const int given = (o.holdout > 0) + !o.holdoutCampaign.empty() + !o.holdoutTable.empty();
    if (given != 1)
        throw InputError("--holdout / --holdout-campaign / --holdout-table", given ? "(several)" : "(none)", "exactly one of them");
    std::vector<surrogates::Row> train = runs.rows, held;
    if (o.holdout > 0) {
        requireRange("holdout", o.holdout, 1, static_cast<int>(runs.rows.size()) - 5);
        held.assign(runs.rows.end() - o.holdout, runs.rows.end());
        train.resize(train.size() - static_cast<size_t>(o.holdout));
    } else {
        SurrogateCmd h = o;
        h.campaign = o.holdoutCampaign, h.table = o.holdoutTable;
        if (h.campaign == o.campaign && h.table == o.table)
            throw InputError("holdout", h.campaign + h.table, "runs other than the training ones");
        held = loadRuns(h, heldSource).rows;
        if (held.empty()) throw InputError("holdout", h.campaign + h.table, "finished, steady runs");
    }
    std::vector<int> sizes = o.sizes;
    // About six sizes from 8 (or fewer, or the fewest a linear trend takes) to every training run,
    // evenly in log.
    const double first = std::max(8.0, o.trend == "linear" ? surrogates::modelInputs(o.similarity).size() + 2.0 : 0.0);
    if (sizes.empty())
        for (double n = std::min<double>(first, static_cast<double>(train.size())); ; n *= 1.4) {
            const int k = std::min(static_cast<int>(std::lround(n)), static_cast<int>(train.size()));
            if (sizes.empty() || k > sizes.back()) sizes.push_back(k);
            if (k == static_cast<int>(train.size())) break;
        }
    const auto c = surrogates::learningCurve(train, held, f, sizes);
    const auto law = surrogates::powerLawOf(c, o.target);
    const std::string label = o.kind + (o.similarity ? " (similarity)" : "") + ", " + std::to_string(held.size()) + " hold-out runs" +
                              (o.holdoutCampaign.empty() ? "" : " of " + o.holdoutCampaign);
    const auto files = surrogates::writeLearningCurve(c, law, label, o.out);
    nlohmann::json points = nlohmann::json::array();
    for (const auto& p : c)
        points.push_back({{"n", p.n}, {"holdout_mean", p.mean}, {"holdout_ci90", {p.lo, p.hi}}, {"holdout_max", p.max},
                          {"coverage95", std::isnan(p.coverage) ? nlohmann::json() : nlohmann::json(p.coverage)}, {"loo_mean", p.looMean}});
    const nlohmann::json out{{"source", source}, {"holdout_source", heldSource.is_null() ? nlohmann::json("last runs of the source") : heldSource},
                             {"kind", o.kind}, {"similarity", o.similarity}, {"n_holdout", held.size()},
                             {"points", points}, {"power_law", law}, {"files", files}};
    if (o.json) {
        std::cout << out.dump(2) << '\n';
        return 0;
    }
    std::cout << "learning curve of the " << label << '\n';
    for (const auto& p : c)
        std::cout << "  " << std::setw(4) << p.n << " runs: hold-out mean " << pct(p.mean) << " (90% bootstrap " << pct(p.lo) << " .. "
                  << pct(p.hi) << "), leave-one-out " << pct(p.looMean) << '\n';
    if (!law.is_null()) {
        std::cout << "  power law: error ~ n^-" << std::setprecision(3) << law["exponent"].get<double>();
        if (!law["runs_for_target"].is_null())
            std::cout << "; " << pct(o.target) << " at about " << std::lround(law["runs_for_target"].get<double>()) << " runs (extrapolated)";
        std::cout << '\n';
    }
    std::cout << "  table " << files["table"].get<std::string>() << '\n';
    return 0;
}

int info(const SurrogateCmd& o) {
    const auto m = surrogates::Surrogate::load(o.model);
    auto j = m.toJson();
    nlohmann::json out{{"model", o.model},      {"kind", j["kind"]},          {"inputs", j["inputs"]},
                       {"model_inputs", j["model_inputs"]}, {"output", j["output"]}, {"validation", j["validation"]}, {"provenance", j["provenance"]},
                       {"checks", j["checks"]}, {"warnings", m.warnings()},   {"n_train", m.trainingIds().size()}};
    if (m.kind() == "regimes") {
        out["parts"] = j["validation"]["parts"];
    } else if (m.kind() == "rsm") {
        const auto& mod = j["model"];
        nlohmann::json terms = nlohmann::json::array();
        std::vector<std::string> names;
        for (const auto& s : m.inputs()) names.push_back(s.name);
        for (size_t k = 0; k < mod["terms"].size(); ++k) {
            const surrogates::Term t{mod["terms"][k][0].get<int>(), mod["terms"][k][1].get<int>()};
            terms.push_back({{"term", t.name(names)},
                             {"coefficient", mod["coefficients"][k]},
                             {"standard_error", mod["standard_errors"][k]}});
        }
        out["coefficients"] = terms;
        out["press"] = mod["press"];
    } else {
        const auto& mod = j["model"];
        nlohmann::json lengths = nlohmann::json::object();
        for (size_t k = 0; k < m.inputs().size() && k < mod["lengthScales"].size(); ++k)
            lengths[m.inputs()[k].name] = mod["lengthScales"][k];
        out["hyperparameters"] = {{"kernel", mod.value("kernel", "")},
                                  {"trend", mod.value("trend", "")},
                                  {"length_scales", lengths},  // in scaled inputs, [0, 1] over the box
                                  {"nugget", mod["nugget"]},
                                  {"process_variance", mod["processVariance"]},
                                  {"log_likelihood", mod["logLikelihood"]}};
    }
    if (o.json) {
        std::cout << out.dump(2) << '\n';
        return 0;
    }
    const auto& v = out["validation"];
    std::cout << o.model << ": " << m.kind() << " model of M [kg], " << v.value("transform", "") << ", trained on "
              << m.trainingIds().size() << " runs\n  created " << out["provenance"].value("created_utc", "") << " by mixload "
              << out["provenance"].value("mixload_version", "") << " (" << out["provenance"].value("git_commit", "") << ")\n"
              << "  belongs to " << m.sourceLabel() << "\n  source " << out["provenance"]["source"].dump()
              << "\n  training box (model inputs):\n";
    for (const auto& in : out["model_inputs"])
        std::cout << "    " << std::left << std::setw(10) << in["name"].get<std::string>() << std::right << std::setw(12)
                  << in["min"].get<double>() << " .. " << std::setw(12) << in["max"].get<double>() << " "
                  << in["unit"].get<std::string>() << (in["log"].get<bool>() ? "  (log)" : "") << '\n';
    std::cout << "  leave-one-out: mean " << pct(v["mean_rel_error"]) << ", max " << pct(v["max_rel_error"])
              << ", 95% coverage " << pct(v["coverage95"]) << '\n';
    if (out.contains("coefficients")) {
        std::cout << "  terms (scaled inputs in [-1, 1]; coefficient, standard error):\n";
        for (const auto& t : out["coefficients"])
            std::cout << "    " << std::left << std::setw(20) << t["term"].get<std::string>() << std::right << std::setw(14)
                      << t["coefficient"].get<double>() << std::setw(14) << t["standard_error"].get<double>() << '\n';
    } else if (out.contains("hyperparameters")) {
        std::cout << "  hyperparameters " << out["hyperparameters"].dump() << '\n';
    } else {
        printParts(out["parts"]);
    }
    std::cout << "  checks recorded: " << out["checks"].size() << '\n';
    for (const auto& w : out["warnings"]) std::cout << "  warning: " << w.get<std::string>() << '\n';
    return 0;
}

// Every checked run, worst first: which runs a model misses, and where they lie.
void printRuns(const nlohmann::json& r) {
    using Judged = std::pair<const nlohmann::json*, const char*>;
    std::vector<Judged> all;
    for (const auto& e : r["holdout"]) all.emplace_back(&e, e["in_training_box"].get<bool>() ? "hold-out" : "hold-out, outside the box");
    for (const auto& e : r["loo"]["runs"]) all.emplace_back(&e, "leave-one-out");
    std::stable_sort(all.begin(), all.end(), [](const Judged& a, const Judged& b) {
        return (*a.first)["rel_error"].get<double>() > (*b.first)["rel_error"].get<double>();
    });
    const auto num = [](const nlohmann::json& v, int digits) {
        std::ostringstream s;
        if (v.is_number()) s << std::fixed << std::setprecision(digits) << v.get<double>();
        else s << "n/a";
        return s.str();
    };
    int idWidth = 4;
    for (const auto& [e, how] : all) idWidth = std::max(idWidth, static_cast<int>((*e)["id"].get<std::string>().size()) + 2);
    std::cout << "  runs, worst first:\n  " << std::left << std::setw(idWidth) << "id" << std::right << std::setw(7) << "rpm"
              << std::setw(8) << "feed" << std::setw(7) << "mu_s" << std::setw(10) << "M [kg]" << std::setw(10) << "model"
              << std::setw(20) << "95% interval" << std::setw(10) << "error" << "  judged by\n";
    for (const auto& [e, how] : all) {
        const auto& x = (*e)["inputs"];
        const auto& ci = (*e)["ci95_kg"];
        std::cout << "  " << std::left << std::setw(idWidth) << (*e)["id"].get<std::string>() << std::right << std::setw(7)
                  << num(x["rpm"], 1) << std::setw(8) << num(x["feed_kg_h"], 2) << std::setw(7) << num(x["mu_s"], 3)
                  << std::setw(10) << num((*e)["loading_kg"], 4) << std::setw(10) << num((*e)["predicted_kg"], 4)
                  << std::setw(20) << (num(ci[0], 4) + " .. " + num(ci[1], 4)) << std::setw(10) << pct((*e)["rel_error"])
                  << "  " << how << '\n';
    }
}

}  // namespace

int runCheck(const std::string& modelPath, const std::string& campaign, const std::string& dir, const std::string& table,
             std::optional<double> threshold, bool record, bool json, bool quiet, bool listRuns, const std::string& plotDir) {
    auto m = surrogates::Surrogate::load(modelPath);
    SurrogateCmd o;
    // The runs are labelled as the model's were (models before issue 64 kept every point's own run).
    o.twoStates = m.provenance().value("options", nlohmann::json::object()).value("two_states", std::string("keep"));
    o.campaign = campaign;
    o.dir = dir;
    o.table = table;
    if (o.campaign.empty() && o.table.empty()) {
        // The runs the model was trained on: its table (a shipped model's is the campaign's export
        // under data/, found there from any directory), else its campaign.
        const auto& src = m.provenance().value("source", nlohmann::json::object());
        if (src.contains("table")) {
            std::filesystem::path t = src["table"].get<std::string>();
            if (!std::filesystem::exists(t) && t.is_relative() && *t.begin() == "data")
                t = std::filesystem::path(MIXLOAD_DATA_DIR) / t.lexically_relative("data");
            o.table = t.string();
        } else if (src.contains("campaign")) {
            o.campaign = src["campaign"];
            const std::string ledger = src.value("ledger", std::string());
            const auto cut = ledger.rfind("/" + o.campaign + "/ledger.sqlite");
            if (cut != std::string::npos) o.dir = ledger.substr(0, cut);
        } else {
            throw InputError("--campaign / --table", "(neither)", "the runs to check against");
        }
    }
    nlohmann::json source;
    const auto runs = loadRuns(o, source);
    auto r = surrogates::checkModel(m, runs);
    r["model"] = modelPath;
    r["source"] = source;
    r["threshold"] = threshold ? nlohmann::json(*threshold) : nlohmann::json();
    // The runs' own scatter, measured by the campaign's replicates, is the floor under any model's
    // error on them: it belongs beside the error.
    r["label_noise"] = nlohmann::json();
    if (!o.campaign.empty())
        if (const auto noise = experiments::campaignNoise({o.campaign, o.dir}); noise["n"].get<int>() > 0)
            r["label_noise"] = {{"replicate_pairs", noise["n"]}, {"run_noise", noise["run_noise"]}};
    // Runs of another scene (another mesh, method or base) measure another model: their errors are
    // shown, never added to this model's history.
    const auto modelBase = m.provenance().value("source", nlohmann::json::object()).value("base", nlohmann::json());
    const auto runsBase = source.value("base", nlohmann::json());
    r["same_scene"] = modelBase.is_null() || runsBase.is_null() ? nlohmann::json() : nlohmann::json(modelBase == runsBase);
    if (r["same_scene"] == false) {
        std::cerr << "mixload: warning: these runs are of another scene than the model's (runs " << runsBase.dump() << ", model "
                  << modelBase.dump() << "): not recorded in its check history\n";
        record = false;
    }
    // A check of the same runs gives the same figures, whoever asks (a campaign driver's --check, then
    // the landing's check of the exported table): the history keeps it once.
    const auto& history = m.checkHistory();
    const bool alreadyRecorded = record && !history.empty() && [&] {
        const auto& last = history.back();
        for (const char* k : {"n_holdout", "mean_rel_error", "max_rel_error", "coverage95"})
            if (last.value(k, nlohmann::json()) != r[k]) return false;
        // A record from before the per-regime figures is taken again once, with them.
        return last["loo"].value("mean_rel_error", nlohmann::json()) == r["loo"]["mean_rel_error"] &&
               last.contains("holdout_by_regime");
    }();
    r["already_recorded"] = alreadyRecorded;
    if (alreadyRecorded) record = false;
    if (record) {
        auto looFigures = r["loo"];
        looFigures.erase("runs");  // the per-run list is printed, not kept: the history keeps the figures
        m.checks().push_back({{"date_utc", utcNow()},
                              {"source", source},
                              {"n_holdout", r["n_holdout"]},
                              {"mean_rel_error", r["mean_rel_error"]},
                              {"mean_rel_error_ci90", r["mean_rel_error_ci90"]},
                              {"max_rel_error", r["max_rel_error"]},
                              {"coverage95", r["coverage95"]},
                              {"holdout_by_regime", r["holdout_by_regime"]},
                              {"loo", looFigures},
                              {"mixload_version", kVersion},
                              {"git_commit", kGitCommit}});
        m.save(modelPath);
    }
    if (!plotDir.empty()) {
        std::ostringstream title;
        // The title carries the hold-out's figures, or the leave-one-out's when every run trained the model.
        const bool held = r["n_holdout"].get<int>() > 0;
        const auto& f = held ? r : r["loo"];
        title << std::filesystem::path(modelPath).filename().string() << ": " << (held ? r["n_holdout"] : r["loo"]["n"])
              << (held ? " hold-out runs" : " training runs, leave-one-out") << ", mean " << pct(f["mean_rel_error"]) << ", max "
              << pct(f["max_rel_error"]) << ", 95% coverage " << pct(f["coverage95"]);
        std::string warning;
        const auto png = surrogates::plotCheck(r, title.str(), plotDir, warning);
        r["plot"] = png ? nlohmann::json(png->string()) : nlohmann::json();
        if (!png) std::cerr << "mixload: warning: no parity plot: " << warning << '\n';
    }
    const bool failed = threshold && !r["mean_rel_error"].is_null() && r["mean_rel_error"].get<double>() > *threshold;
    r["passed"] = !failed;
    if (quiet) {
    } else if (json) {
        std::cout << r.dump(2) << '\n';
    } else {
        const auto ci = [](const nlohmann::json& v) {
            return v.is_null() ? std::string() : " (90% bootstrap " + pct(v[0]) + " .. " + pct(v[1]) + ")";
        };
        std::cout << "check of " << modelPath << " against " << runs.rows.size() << " full runs\n  hold-out ("
                  << r["n_holdout"] << " runs): mean " << pct(r["mean_rel_error"]) << ci(r["mean_rel_error_ci90"]) << ", max "
                  << pct(r["max_rel_error"]) << " relative error, 95% interval coverage " << pct(r["coverage95"]);
        if (const auto& b = r["holdout_in_box"]; b["n"] != r["n_holdout"])
            std::cout << "\n    of which inside the training box (" << b["n"] << " runs): mean " << pct(b["mean_rel_error"])
                      << ci(b["mean_rel_error_ci90"]) << ", max " << pct(b["max_rel_error"]) << ", coverage "
                      << pct(b["coverage95"]);
        std::cout << "\n  leave-one-out (" << r["loo"]["n"] << " training runs): mean " << pct(r["loo"]["mean_rel_error"])
                  << ci(r["loo"]["mean_rel_error_ci90"]) << ", max " << pct(r["loo"]["max_rel_error"]) << ", coverage "
                  << pct(r["loo"]["coverage95"]) << '\n';
        // Per regime (surrogates/regime.hpp): one mean hides a model good on beds and poor across the transition.
        std::cout << "  by regime            hold-out: n   mean (90% bootstrap)        max   cover95 | leave-one-out: n   mean    max   cover95\n";
        for (const char* regime : {"bed", "transition", "film"}) {
            const auto& h = r["holdout_by_regime"][regime];
            const auto& l = r["loo"]["by_regime"][regime];
            const auto range = [](const nlohmann::json& v) { return v.is_null() ? std::string("") : pct(v[0]) + " .. " + pct(v[1]); };
            std::cout << "    " << std::left << std::setw(20) << regime << std::right << std::setw(9) << h["n"].get<int>() << "  "
                      << std::setw(7) << pct(h["mean_rel_error"]) << " (" << std::setw(17) << range(h["mean_rel_error_ci90"]) << ")  "
                      << std::setw(7) << pct(h["max_rel_error"]) << "  " << std::setw(6) << pct(h["coverage95"]) << " | "
                      << std::setw(15) << l["n"].get<int>() << "  " << std::setw(6) << pct(l["mean_rel_error"]) << "  "
                      << std::setw(6) << pct(l["max_rel_error"]) << "  " << std::setw(6) << pct(l["coverage95"]) << '\n';
        }
        if (!r["label_noise"].is_null())
            std::cout << "  label noise of these runs (" << r["label_noise"]["replicate_pairs"]
                      << " replicate pairs, campaign noise): one run's scatter " << pct(r["label_noise"]["run_noise"])
                      << ", a floor under any model's error at such points\n";
        if (listRuns) printRuns(r);
        if (r.contains("plot") && !r["plot"].is_null()) std::cout << "  plot: " << r["plot"].get<std::string>() << '\n';
        if (record) std::cout << "  recorded in the model's check history\n";
        if (alreadyRecorded)
            std::cout << "  already in the model's check history (" << history.back()["date_utc"].get<std::string>()
                      << "): not recorded again\n";
    }
    if (failed)
        std::cerr << "mixload: check failed: mean hold-out error " << pct(r["mean_rel_error"]) << " exceeds --threshold "
                  << pct(*threshold) << '\n';
    return failed ? 1 : 0;
}

namespace {

// The runs a model learns from and how it is fitted: shared by `surrogate fit` and `surrogate curve`.
void addFitOptions(CLI::App* c, SurrogateCmd* o) {
    c->add_option("--campaign", o->campaign, "Mixer campaign whose finished, steady runs train the model");
    c->add_option("--dir", o->dir, "Where campaigns live")->capture_default_str();
    c->add_option("--table", o->table, "CSV instead of a campaign (columns as `campaign export` writes)");
    c->add_option("--kind", o->kind,
                  "rsm | kriging | regimes (a kriging model per flow regime: bed below 140 rpm, film above 205 rpm, the band between; blended over a few rpm)")
        ->capture_default_str();
    c->add_option("--two-states", o->twoStates,
                  "A point whose replicate sits in another steady state (loadings more than 1.5 times apart): protocol (train on the run "
                  "started nearest the label protocol's 0.05 kg deposit) | drop (leave the point out) | keep (the point's own run)")
        ->capture_default_str();
    c->add_option("--transform", o->transform, "auto (by leave-one-out error) | none | log (log M, log of d, rho, feed, rpm)")
        ->capture_default_str();
    c->add_flag("--similarity", o->similarity,
                "Fit M/rho in the similarity variables mu_s, mu_d, d/i0, feed/rho, rpm (exact in the model up to the air's inertia; README, Exact similarity)");
    c->add_option("--noise", o->noise, "kriging: relative scatter of a run's loading (e.g. 0.01): the nugget is kept at or above it")
        ->capture_default_str();
    c->add_flag("--no-select", o->noSelect, "rsm: keep every term of the full quadratic (no PRESS selection)");
    c->add_option("--kernel", o->kernel, "kriging: matern52 | se")->capture_default_str();
    c->add_option("--trend", o->trend, "kriging: constant | linear")->capture_default_str();
    c->add_option("--trend-inputs", o->trendInputs,
                  "kriging: a linear trend in these model inputs only, e.g. feed/rho,rpm (with --transform log: a power law in them)")
        ->delimiter(',');
    c->add_option("--objective", o->objective, "kriging: hyperparameters by likelihood | loo (closed-form leave-one-out error)")
        ->capture_default_str();
    c->add_option("--starts", o->starts, "kriging: multistart count of the likelihood optimisation")->capture_default_str();
    c->add_option("--seed", o->seed, "kriging: seed of the multistart")->capture_default_str();
}

}  // namespace

void addSurrogate(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand("surrogate", "Fit and inspect surrogate models of the mixer loading M");
    cmd->require_subcommand(1);
    auto o = std::make_shared<SurrogateCmd>();

    auto* f = cmd->add_subcommand("fit", "Fit a response surface or kriging model to full runs");
    addFitOptions(f, o.get());
    f->add_option("-o,--output", o->output, "Model file to write (.json)")->required();
    f->add_option("--holdout", o->holdout, "Keep the last N runs out of training (for `mixload check`)")->capture_default_str();
    f->add_flag("--json", o->json, "Print JSON");
    f->callback([&action, o] { action = [o] { return fit(*o); }; });

    auto* cv = cmd->add_subcommand("curve", "Learning curve: hold-out error against the number of training runs (the last --holdout runs, or another campaign's, fixed as the hold-out)");
    addFitOptions(cv, o.get());
    cv->add_option("--holdout", o->holdout, "The last N runs: the fixed hold-out");
    cv->add_option("--holdout-campaign", o->holdoutCampaign,
                   "Instead of --holdout: the finished, steady runs of this campaign (same --dir) are the hold-out, e.g. a hold-out design of its own");
    cv->add_option("--holdout-table", o->holdoutTable, "Instead of --holdout: the runs of this CSV (as `campaign export` writes) are the hold-out");
    cv->add_option("--sizes", o->sizes, "Training-set sizes (default: about six from 8 to all, even in log)")->delimiter(',');
    cv->add_option("--target", o->target, "Error the power law is extrapolated to (runs needed)")->capture_default_str();
    cv->add_option("--out", o->out, "Directory for curve.md, .csv and .png")->capture_default_str();
    cv->add_flag("--json", o->json, "Print JSON");
    cv->callback([&action, o] { action = [o] { return curve(*o); }; });

    auto* i = cmd->add_subcommand("info", "Print a model's inputs, training box, coefficients, validation and provenance");
    i->add_option("MODEL", o->model, "Model file")->required();
    i->add_flag("--json", o->json, "Print JSON");
    i->callback([&action, o] { action = [o] { return info(*o); }; });

    auto* c = app.add_subcommand("check", "Compare a model with every full run it was not trained on (and LOO for the rest)");
    c->add_option("--model", o->model, "Model file (default: the shipped kriging model)");
    c->add_option("--campaign", o->campaign, "Mixer campaign (default: the model's own)");
    c->add_option("--dir", o->dir, "Where campaigns live")->capture_default_str();
    c->add_option("--table", o->table, "CSV of full runs instead of a campaign");
    c->add_option("--threshold", o->threshold, "Exit 1 when the mean hold-out relative error exceeds this (e.g. 0.05)");
    c->add_flag("--no-record", o->noRecord, "Do not append the result to the model's check history");
    c->add_flag("--runs", o->listRuns, "Also list every run (inputs, M, the model's answer, error), worst first");
    c->add_option("--plot", o->plot, "Directory for parity.png: each run's M against the model's answer and its 95% interval");
    c->add_flag("--json", o->json, "Print JSON");
    c->callback([&action, o] {
        action = [o] {
            return runCheck(o->model.empty() ? defaultModelPath() : o->model, o->campaign, o->dir, o->table, o->threshold,
                            !o->noRecord, o->json, false, o->listRuns, o->plot);
        };
    });
}

}  // namespace mixload::app
