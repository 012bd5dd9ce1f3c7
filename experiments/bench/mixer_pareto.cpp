// SPDX-License-Identifier: GPL-3.0-or-later
#include "bench/mixer_pareto.hpp"

#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <sstream>

#include "bench/pareto.hpp"
#include "campaign/campaign_table.hpp"
#include "cases/meshed_geometry.hpp"
#include "common/atomic_file.hpp"
#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "common/stats.hpp"
#include "model.hpp"
#include "rom/regression/campaign_regression.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {
using Clock = std::chrono::steady_clock;

// A campaign's steady runs by design index: the point's parameters, its loading and its cost.
struct SteadyRun {
    nlohmann::json params;
    surrogates::Point x{};
    double m = 0, coreSeconds = 0;
};
struct SteadyRuns {
    store::CampaignInfo info;
    std::map<int, SteadyRun> runs;
    double coreSeconds = 0;  // every finished run's, steady or not: what the campaign cost
    scene::MixerScene scene() const { return mixerSceneFor(info.sceneJson, nlohmann::json::object()); }
    std::string mesh() const {
        return formatNumber(scene().cellSize * 100) + " cm";
    }
};

SteadyRuns steadyRuns(const CampaignPlace& place) {
    std::unique_ptr<store::Ledger> l;
    SteadyRuns s{openCampaign(place, l), {}, 0};
    if (s.info.scene != "mixer") throw InputError("campaign", place.name, "a mixer campaign");
    for (const auto& r : l->runs(place.name)) {
        if (r.status == "done") s.coreSeconds += r.coreSeconds.value_or(0);
        const auto m = runQuantity(r, s.info.scene);
        if (!m || store::isReplicate(r)) continue;  // not steady, or a replicate
        s.runs[r.index] = {r.params, mixerInputs(s.info.sceneJson, r.params), *m, r.coreSeconds.value_or(0)};
    }
    return s;
}

// The design's own inputs (the scene hash differs between meshes).
bool samePoint(const nlohmann::json& a, const nlohmann::json& b) {
    for (const auto& [k, v] : a.items()) {
        if (k == "scene_hash" || !v.is_number()) continue;
        if (!b.contains(k)) return false;
        const double x = v.get<double>(), y = b[k].get<double>();
        if (std::abs(x - y) > 1e-9 * std::max(std::abs(x), std::abs(y))) return false;
    }
    return true;
}

// Median seconds of one prediction at each point (each timed over enough repetitions to rise above
// the clock's resolution), and the predictions.
std::pair<double, std::vector<double>> timedPredictions(const surrogates::Surrogate& s, const std::vector<surrogates::Point>& xs) {
    auto ws = s.makeWorkspace();
    std::vector<double> m, t;
    for (const auto& x : xs) {
        m.push_back(s.predict(x, ws).m);
        constexpr int reps = 2000;
        // Each answer is stored through a volatile, so the repetitions cannot be optimised away.
        volatile double sink = 0;
        const auto t0 = Clock::now();
        for (int i = 0; i < reps; ++i) sink = s.predict(x, ws).m;
        t.push_back(secondsSince(t0) / reps);
    }
    return {median(t), m};
}
}  // namespace

nlohmann::json runMixerPareto(const MixerPareto& b) {
    const auto train = steadyRuns(b.train), ref = steadyRuns(b.holdout);
    if (train.runs.size() < 5)
        throw InputError("campaign", b.train.name + " (" + std::to_string(train.runs.size()) + " steady runs)", "5 or more steady runs");
    if (ref.runs.empty()) throw InputError("holdout", b.holdout.name, "a campaign with a steady run");
    std::vector<SteadyRuns> coarse;
    for (const auto& c : b.coarse) {
        coarse.push_back(steadyRuns(c));
        cases::requireSameImpeller(ref.scene(), coarse.back().scene(), "coarse", c.name);
        for (const auto& [i, r] : coarse.back().runs)
            if (ref.runs.count(i) && !samePoint(ref.runs.at(i).params, r.params))
                throw InputError("coarse", c.name, "the hold-out's design (point " + std::to_string(i) + " differs)");
    }
    std::vector<int> idx;
    std::vector<surrogates::Point> xs;
    for (const auto& [i, r] : ref.runs) idx.push_back(i), xs.push_back(r.x);

    // Per hold-out run, each method's M; errors relative to the reference run.
    std::map<std::string, std::map<int, double>> answer;
    std::vector<ParetoMethod> methods;
    const auto add = [&](const std::string& name, double seconds, double offline) {
        std::vector<double> e;
        for (const auto& [i, m] : answer[name]) e.push_back(std::abs(m / ref.runs.at(i).m - 1));
        if (e.empty()) return;
        double mean = 0, worst = 0;
        for (const double v : e) mean += v / static_cast<double>(e.size()), worst = std::max(worst, v);
        methods.push_back({name + " (" + std::to_string(e.size()) + ")", seconds, median(e), {median(e), mean, worst}, offline, false, false});
    };
    {
        std::vector<double> t;
        for (const auto& [i, r] : ref.runs) t.push_back(r.coreSeconds);
        methods.push_back({"full run, " + ref.mesh() + " (reference, " + std::to_string(t.size()) + ")", median(t), 0, {0, 0, 0}, 0, true, false});
    }
    for (size_t k = 0; k < coarse.size(); ++k) {
        const std::string name = "full run, " + coarse[k].mesh() + ", " + b.coarse[k].name;
        std::vector<double> t;
        for (const auto& [i, r] : coarse[k].runs)
            if (ref.runs.count(i)) answer[name][i] = r.m, t.push_back(r.coreSeconds);
        add(name, median(t), 0);
    }
    // The loading surrogate as `surrogate fit --similarity [--kind rsm]` fits it on the training runs.
    // Its nugget is kept at or above the label noise the training campaign's replicates measured
    // (`campaign noise`, what `surrogate fit --noise` takes), as issue 16's models are fitted.
    nlohmann::json provenance;
    const auto table = campaignTable(b.train.name, b.train.dir, provenance);
    const auto noise = campaignNoise(b.train)["run_noise"];
    for (const std::string kind : {"kriging", "rsm"}) {
        surrogates::FitOptions fo;
        fo.kind = kind;
        fo.similarity = true;
        fo.noise = noise.is_number() ? noise.get<double>() : 0.0;
        const auto t0 = Clock::now();
        const auto s = surrogates::Surrogate::fit(table.rows, fo, provenance);
        const double fit = secondsSince(t0);
        const auto [seconds, m] = timedPredictions(s, xs);
        const std::string name = kind == "kriging" ? "kriging (loading surrogate)" : "response surface";
        for (size_t j = 0; j < idx.size(); ++j) answer[name][idx[j]] = m[j];
        add(name, seconds, train.coreSeconds + fit);
    }
    // POD regression of the final field, as `rom regression --holdout` runs it, of alpha and of
    // ln alpha on fields read once; it needs both campaigns' snapshots, and says so when they are
    // missing. Offline: the training campaign, the reading and the regression's own fit.
    nlohmann::json notes = nlohmann::json::array();
    std::vector<rom::RegressionCheckOptions> variants(2);
    for (size_t v = 0; v < variants.size(); ++v) {
        variants[v].mixerInputs = mixerInputs;
        variants[v].logField = v == 1;
        variants[v].surrogateNoise = noise.is_number() ? noise.get<double>() : 0.0;
    }
    try {
        const auto results = rom::campaignRegressionHoldouts(b.train.ledger(), b.train.name, b.holdout.ledger(), b.holdout.name, variants);
        for (size_t v = 0; v < results.size(); ++v) {
            const auto& j = results[v];
            const bool alpha = !variants[v].logField;
            const std::string name = alpha ? "POD regression of alpha" : "POD regression of ln(alpha)";
            const std::string steady = "reduced steady transport on the regressed U";
            for (const auto& r : j["rows"]) {
                const int i = r["run"].get<int>();
                if (!ref.runs.count(i)) continue;
                answer[name][i] = r["loading_kg"]["pod_regression"].get<double>();
                if (alpha && r["loading_kg"].contains("steady_model")) answer[steady][i] = r["loading_kg"]["steady_model"].get<double>();
            }
            const double offline = train.coreSeconds + j["load_seconds"].get<double>() + j["fit_seconds"].get<double>();
            add(name, j["predict_seconds"].get<double>(), offline);
            if (alpha && j["summary"]["loading_kg"].contains("steady_model_seconds"))
                add(steady, j["summary"]["loading_kg"]["steady_model_seconds"].get<double>(), offline);
        }
    } catch (const InputError& e) {
        notes.push_back(std::string("POD regression: ") + e.what());
    }

    // Per run: every method's answer beside the reference.
    std::ostringstream md, csv;
    md << "| hold-out run | reference M [kg] |";
    csv << "run,reference_kg";
    for (const auto& [name, a] : answer) md << ' ' << name << " |", csv << ",\"" << name << '"';
    md << "\n|---|---|";
    for (size_t k = 0; k < answer.size(); ++k) md << "---|";
    md << '\n';
    csv << '\n';
    nlohmann::json rows = nlohmann::json::array();
    for (const int i : idx) {
        const double m0 = ref.runs.at(i).m;
        md << "| " << i << " | " << formatNumber(m0) << " |";
        csv << i << ',' << m0;
        nlohmann::json row{{"run", i}, {"reference_kg", m0}};
        for (const auto& [name, a] : answer) {
            const auto it = a.find(i);
            if (it == a.end()) {
                md << " – |", csv << ',';
                continue;
            }
            std::ostringstream cell;
            cell << formatNumber(it->second) << " (" << (it->second >= m0 ? "+" : "") << formatNumber(std::round((it->second / m0 - 1) * 1e3) / 10) << "%)";
            md << ' ' << cell.str() << " |";
            csv << ',' << it->second;
            row[name] = it->second;
        }
        md << '\n';
        csv << '\n';
        rows.push_back(row);
    }
    // Each method against the loading surrogate on the runs both answered, run by run: whether the
    // hold-out can tell them apart (the paired difference's 90% bootstrap interval).
    const std::string krig = "kriging (loading surrogate)";
    nlohmann::json paired = nlohmann::json::array();
    if (answer.count(krig)) {
        md << "\n| method, paired with " << krig << " | runs | difference of the mean relative errors [points] | 90% bootstrap interval |\n|---|---|---|---|\n";
        for (const auto& [name, a] : answer) {
            if (name == krig) continue;
            std::vector<double> d;
            for (const auto& [i, m] : a)
                if (const auto k = answer[krig].find(i); k != answer[krig].end())
                    d.push_back(std::abs(m / ref.runs.at(i).m - 1) - std::abs(k->second / ref.runs.at(i).m - 1));
            if (d.size() < 2) continue;
            double mean = 0;
            for (const double v : d) mean += v / static_cast<double>(d.size());
            const auto ci = bootstrapMeanInterval90(d);
            paired.push_back({{"method", name}, {"runs", d.size()}, {"mean_abs_error_minus_kriging", mean}, {"ci90", {ci[0], ci[1]}}});
            md << "| " << name << " | " << d.size() << " | " << formatNumber(std::round(mean * 1e3) / 10) << " | "
               << formatNumber(std::round(ci[0] * 1e3) / 10) << " .. " << formatNumber(std::round(ci[1] * 1e3) / 10) << " |\n";
        }
    }
    fs::create_directories(b.out);
    writeFileAtomic(b.out / "runs.md", md.str());
    writeFileAtomic(b.out / "runs.csv", csv.str());

    const std::string n = std::to_string(idx.size());
    const ParetoPlot plot{"Mixer loading M, " + n + " steady hold-out runs of `" + b.holdout.name + "` (" + ref.mesh() +
                              "), models fitted on the " + std::to_string(train.runs.size()) + " steady runs of `" + b.train.name +
                              "`; error: |relative error| in M against the hold-out's full run; time: a full run's "
                              "core-seconds (ledger), a model's wall time per answer here; offline: the training "
                              "campaign's core-seconds plus the fit. The count after a method: hold-out runs it answered.",
                          "Mixer loading: time against error, " + n + " hold-out runs",
                          "time per answer [s] (median; full runs: core-seconds)",
                          "median |relative error| in M",
                          {"median M error", "mean M error", "max M error"},
                          {"median_error", "mean_error", "max_error"}};
    nlohmann::json out{{"train", b.train.name},
                       {"holdout", b.holdout.name},
                       {"coarse", nlohmann::json::array()},
                       {"train_steady_runs", train.runs.size()},
                       {"holdout_steady_runs", idx.size()},
                       {"train_core_seconds", train.coreSeconds},
                       {"surrogate_noise", noise},
                       {"runs", rows},
                       {"paired_with_kriging", paired},
                       {"runs_table", (b.out / "runs.md").string()},
                       {"notes", notes}};
    for (const auto& c : b.coarse) out["coarse"].push_back(c.name);
    out.update(writePareto(b.out, plot, methods));
    return out;
}

}  // namespace mixload::experiments
