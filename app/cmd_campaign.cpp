// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload campaign`: parses, calls experiments/campaign, prints.

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <iostream>

#include "app/commands.hpp"
#include "campaign/campaign.hpp"
#include "campaign/rebase.hpp"
#include "campaign/retry.hpp"
#include "common/input_error.hpp"
#include "common/process.hpp"
#include "store/campaign_fields.hpp"

namespace mixload::app {

namespace {

struct CampaignCmd {
    experiments::CampaignSpec spec;
    std::string output;
    experiments::CampaignRunOptions run;
    bool json = false, adaptive = false, perCoreHour = false;
    double depositFactor = 0.5, inset = 0;
    int point = -1;
    std::string checkModel, criterion = "variance";
    std::vector<std::string> warmFrom;
};

int printCreated(const CampaignCmd& o) {
    const auto j = experiments::createCampaign(o.spec);
    if (o.json) std::cout << j.dump(2) << '\n';
    else
        std::cout << "campaign " << o.spec.place.name << ": " << j["points"] << " " << j["scene"].get<std::string>()
                  << " points (" << j["design"].get<std::string>()
                  << (j["protocol"].get<std::string>().empty() ? "" : ", protocol " + j["protocol"].get<std::string>())
                  << "), ledger " << j["ledger"].get<std::string>() << '\n';
    return 0;
}

int printExtended(const CampaignCmd& o) {
    const auto j = experiments::extendCampaign(o.spec.place, o.spec.n, o.adaptive,
                                               o.criterion == "variance" ? experiments::AdaptiveCriterion::Variance
                                                                         : experiments::AdaptiveCriterion::LooWeighted,
                                               o.inset, o.perCoreHour);
    if (o.json) {
        std::cout << j.dump(2) << '\n';
        return 0;
    }
    std::cout << "campaign " << o.spec.place.name << ": " << j["added"] << " points added (" << j["points"] << " in all)\n";
    if (j.contains("adaptive")) {
        const auto& a = j["adaptive"];
        std::cout << "  where the " << a["model"].get<std::string>() << " is least sure (" << a["criterion"].get<std::string>()
                  << "; leave-one-out mean |error| "
                  << a["loo_mean_abs_error_log"].get<double>() << " in log, " << a["pending_runs"] << " queued points conditioned on"
                  << (a["per_core_hour"].get<bool>() ? "; per forecast core-hour" : "") << "):\n";
        for (const auto& p : a["picks"]) {
            std::cout << "    " << p["params"].dump() << "  predicted " << p["predicted"].get<double>() << ", sd "
                      << p["sd_log"].get<double>() << " in log, weight " << p["loo_weight"].get<double>();
            if (!p["core_hours"].is_null()) std::cout << ", ~" << std::setprecision(2) << p["core_hours"].get<double>() << std::setprecision(6) << " core-h";
            std::cout << '\n';
        }
    }
    return 0;
}

int printStatus(const CampaignCmd& o) {
    std::vector<experiments::CampaignPlace> with;
    for (const auto& n : o.warmFrom) with.push_back({n, o.spec.place.dir});
    const auto j = experiments::campaignStatus(o.spec.place, with);
    if (o.json) {
        std::cout << j.dump(2) << '\n';
        return 0;
    }
    const auto& n = j["counts"];
    std::cout << "campaign " << o.spec.place.name << " (" << j["scene"].get<std::string>() << ", "
              << j["design"].get<std::string>() << ", " << j["points"] << " points): " << n["done"] << " done, "
              << n["running"] << " running, " << n["queued"] << " queued, " << n["failed"] << " failed; "
              << j["core_seconds_done"].get<double>() << " core-seconds so far\n";
    for (const auto& u : j["unfinished"]) {
        const std::string attempt = u.value("attempt", "first");
        std::cout << "  point " << u["index"] << " ("
                  << (attempt == "first, left" ? std::string("first attempt, left behind by its retry")
                                               : u["status"].get<std::string>() + (attempt == "retry" ? ", retry" : ""))
                  << "): " << u["time_s"].get<double>()
                  << " s of flow";
        if (u["flow_before_s"].get<double>() > 0)
            std::cout << " (" << u["time_s"].get<double>() + u["flow_before_s"].get<double>() << " s on the point)";
        std::cout << ", M " << u["loading_kg"].get<double>() << " kg (" << u["loading_10s_before_kg"].get<double>()
                  << " kg 10 s before), outflow " << u["outflow_kg_h"].get<double>() << " kg/h";
        if (u["feed_kg_h"].is_number()) std::cout << " against " << u["feed_kg_h"].get<double>() << " kg/h fed";
        std::cout << '\n';
    }
    if (const auto& f = j.value("forecast", nlohmann::json()); f.is_object()) {
        std::printf("forecast (an estimate, %s): about %.1f core-hours left (90%%: %.1f-%.1f) for %zu points\n",
                    f["method"].get<std::string>().c_str(), f["core_hours_left"].get<double>(),
                    f["core_hours_left_90"][0].get<double>(), f["core_hours_left_90"][1].get<double>(), f["points"].size());
        std::printf("  flow to a verdict %.0f s + %.2f residence times, at least %.0f s (median error %.0f%% on the %d runs fitted), "
                    "%.0f core-s per second of flow\n",
                    f["flow_fit"]["intercept_s"].get<double>(), f["flow_fit"]["per_residence_time"].get<double>(),
                    f["flow_fit"]["floor_s"].get<double>(),
                    100 * f["flow_fit"]["median_abs_error"].get<double>(), f["flow_fit"]["runs"].get<int>(),
                    f["core_seconds_per_flow_second"].get<double>());
        for (const auto& p : f["points"])
            std::printf("  point %d%s: M ~ %.3g kg, %.0f of %.0f s of flow run, %.1f core-hours left (90%%: %.1f-%.1f)\n",
                        p["index"].get<int>(), p["replicate"].get<bool>() ? " (replicate)" : "",
                        p["predicted_loading_kg"].get<double>(), p["flow_done_s"].get<double>(),
                        p["flow_to_verdict_s"].get<double>(), p["core_hours_left"].get<double>(),
                        p["core_hours_left_90"][0].get<double>(), p["core_hours_left_90"][1].get<double>());
    }
    if (n["running"].get<int>() > 0 && j["driver_running"] == false)
        std::cout << "no driver is running: the " << n["running"]
                  << " running rows were left by one that stopped, and the next campaign run resumes them\n";
    return 0;
}

int printExported(const CampaignCmd& o) {
    const auto j = experiments::exportCampaignCsv(o.spec.place, o.output);
    if (o.json) std::cout << j.dump(2) << '\n';
    else std::cout << j["rows"] << " rows written to " << o.output << '\n';
    return 0;
}

int printRun(const CampaignCmd& o) {
    requireRange("jobs", o.run.jobs, 1, 64);
    requireRange("np", o.run.np, 1, 256);
    requireRange("max-hours", o.run.maxHours, 0, 1e5);
    auto opt = o.run;
    opt.progress = !o.json;
    if (!o.checkModel.empty())
        // Every new full run is a new test of the model (it never trained on it).
        opt.afterRun = [&o] {
            try {
                runCheck(o.checkModel, o.spec.place.name, o.spec.place.dir, "", std::nullopt, true, false, o.json);
            } catch (const std::exception& e) {
                std::cerr << "mixload: check of " << o.checkModel << " failed: " << e.what() << '\n';
            }
        };
    // SIGTERM or Ctrl-C stops the driver as --max-hours does: its points released, their progress kept.
    stopOnSignals();
    const auto j = experiments::runCampaign(o.spec.place, opt);
    const auto& counts = j["counts"];
    if (o.json) std::cout << j.dump(2) << '\n';
    else
        std::cout << "campaign " << o.spec.place.name << ": " << counts["done"] << " done, " << counts["failed"]
                  << " failed, " << counts["queued"] << " queued"
                  << (j["stopped_at_max_hours"].get<bool>() ? " (stopped at --max-hours; run again to continue)" : "")
                  << (j["stopped_on_request"].get<bool>() ? " (stopped on request; run again to continue)" : "")
                  << '\n';
    // Exit 1 says why on stderr too, with --json as without (an unrecorded result has said so already).
    if (counts["failed"].get<int>() > 0)
        std::cerr << "mixload: campaign " << o.spec.place.name << ": " << counts["failed"]
                  << " runs failed; their errors are in `mixload campaign status " << o.spec.place.name << "`\n";
    return counts["failed"].get<int>() > 0 || j["unrecorded_results"].get<int>() > 0 ? 1 : 0;
}

}  // namespace

void addCampaign(CLI::App& app, Action& action) {
    auto* camp = app.add_subcommand("campaign", "Offline full-CFD campaigns over a design of experiments (SQLite ledger)");
    camp->require_subcommand(1);
    auto o = std::make_shared<CampaignCmd>();

    auto* cr = camp->add_subcommand("create", "Create a campaign: sample the ranges, queue every point in a new ledger");
    cr->add_option("name", o->spec.place.name, "Campaign name")->required();
    cr->add_option("--ranges", o->spec.ranges, "Ranges file (TOML: scene = mixer|collapse, one table per parameter with min, max, unit)")->required();
    cr->add_option("--design", o->spec.design, "lhs (maximin Latin hypercube) | sobol | points (with --points)")->capture_default_str();
    auto* n = cr->add_option("--n", o->spec.n, "Number of points (a sampled design)");
    auto* points = cr->add_option("--points", o->spec.points,
                   "Mixer: the campaign's points from this CSV (columns as a campaign export's: mu_s, mu_d or delta_mu, i0, d, "
                   "rho, feed_kg_h, rpm), each inside the ranges, instead of a sampled design (a relabel of chosen points)");
    n->excludes(points);
    cr->add_option("--protocol", o->spec.protocol,
                   "Mixer: label (default: every point from one fixed 0.05 kg deposit, steady windows of one residence "
                   "time, no warm start; its runs are labels) | scene (the scene's deposit and windows; implied by "
                   "--initial-loading-kg or --steady-window-residence)");
    cr->add_option("--seed", o->spec.seed, "Seed of the Latin hypercube")->capture_default_str();
    cr->add_option("--scene", o->spec.scene, std::string("Mixer: scene name or file (default ") + scene::kDefaultMixerScene +
                                            "); collapse: material (default quartz)");
    cr->add_option("--method", o->spec.method, "Mixer method: mrf | lts | sm")->capture_default_str();
    cr->add_option("--mesh", o->spec.mesh, "Mixer: coarse | medium | fine (default coarse); collapse: cells per column length (default 30)");
    cr->add_option("--cell-size", o->spec.cellSize, "Mixer: explicit cell size [m] instead of --mesh");
    cr->add_option("--end-time", o->spec.endTime, "Mixer: cap on simulated time per run [s]");
    cr->add_option("--initial-loading-kg", o->spec.initialLoadingKg,
                   "Mixer: powder deposited at t = 0 [kg]; near the expected loading shortens each run");
    cr->add_option("--steady-tol", o->spec.steadyTol, "Mixer: steady when consecutive window means of M agree within this fraction");
    cr->add_option("--steady-flow-tol", o->spec.steadyFlowTol, "Mixer: ... and the mean outflow is within this fraction of the feed");
    cr->add_option("--mesher", o->spec.mesher, "Mixer: ogrid | snappy")->capture_default_str();
    cr->add_option("--steady-window-residence", o->spec.steadyResidence,
                   "Mixer: steady-test windows span at least this share of the residence time M/feed (--protocol scene; default 0.5)");
    cr->add_option("--numerics", o->spec.numerics, "Mixer: solver settings preset fast | legacy")
        ->capture_default_str();
    cr->add_option("--dir", o->spec.place.dir, "Where campaigns live")->capture_default_str();
    cr->add_flag("--json", o->json, "Print JSON");
    cr->callback([&action, o] { action = [o] { return printCreated(*o); }; });

    auto* rn = camp->add_subcommand("run", "Run (or continue) a campaign: J runs at a time, resumable after any interruption; SIGTERM or Ctrl-C stops it as --max-hours does");
    rn->add_option("name", o->spec.place.name, "Campaign name")->required();
    rn->add_option("--jobs", o->run.jobs, "Concurrent runs")->capture_default_str();
    rn->add_option("--np", o->run.np, "MPI ranks per run")->capture_default_str();
    rn->add_option("--max-hours", o->run.maxHours, "Stop cleanly after this many hours (0: no limit); unfinished runs resume next time");
    rn->add_option("--dir", o->spec.place.dir, "Where campaigns live")->capture_default_str();
    rn->add_option("--check", o->checkModel, "After each finished run, check this surrogate model against the campaign (mixload check)");
    rn->add_flag("--snapshots", o->run.snapshots, "Keep every written time of each run and export its snapshots.h5");
    rn->add_flag("--warm-nearest", o->run.warmNearest,
                 "Mixer: start each design point from the latest fields of a finished run instead of the scene's deposit: the "
                 "steady run whose loading is nearest a kriging prediction at the point (five steady runs or more), else the "
                 "nearest in the unit cube; replicates keep their deposits. A run's start is in its result (start)");
    rn->add_option("--warm-from-campaign", o->warmFrom,
                   "Mixer: as --warm-nearest, with the finished runs of this campaign (same base scene and mesh; repeatable) "
                   "among the starts, e.g. a hold-out campaign starting from its training campaign's runs");
    rn->add_flag("--json", o->json, "Print JSON");
    rn->callback([&action, o] {
        action = [o] {
            for (const auto& n : o->warmFrom) o->run.warmFrom.push_back({n, o->spec.place.dir});
            return printRun(*o);
        };
    });

    auto* xt = camp->add_subcommand("extend", "Add points to a campaign's design without repeating any (Sobol continues; LHS is augmented)");
    xt->add_option("name", o->spec.place.name, "Campaign name")->required();
    xt->add_option("--n", o->spec.n, "Number of points to add")->required();
    auto* adaptive = xt->add_flag("--adaptive", o->adaptive,
                 "Place the points where a kriging model of the finished runs (log loading of steady runs; collapse: log runout) is least sure, "
                 "given the queued points: one batch per call, e.g. one point per free core");
    xt->add_option("--criterion", o->criterion,
                   "With --adaptive: variance (the model's predictive variance) | loo-weighted (the variance times 1 + the "
                   "squared leave-one-out error of the nearest finished run over its mean: more points where the model misses its runs)")
        ->check(CLI::IsMember({"variance", "loo-weighted"}))
        ->needs(adaptive)
        ->capture_default_str();
    xt->add_option("--inset", o->inset,
                   "With --adaptive: candidates keep this share of each range's width (log-width for a log range) from the "
                   "design box's faces, e.g. the margin the design's ranges were widened by (v2: 0.024); 0 to 0.25")
        ->needs(adaptive)
        ->capture_default_str();
    xt->add_flag("--per-core-hour", o->perCoreHour,
                 "With --adaptive on a mixer campaign: the criterion per core-hour the point is forecast to cost (flow to a "
                 "steady verdict from its predicted loading, as campaign status forecasts): more points where they are cheap")
        ->needs(adaptive);
    xt->add_option("--dir", o->spec.place.dir, "Where campaigns live")->capture_default_str();
    xt->add_flag("--json", o->json, "Print JSON");
    xt->callback([&action, o] { action = [o] { return printExtended(*o); }; });

    auto* rp = camp->add_subcommand("replicate", "Queue finished design points again from another deposit (their pairs measure the steady test's label noise)");
    rp->add_option("name", o->spec.place.name, "Campaign name")->required();
    rp->add_option("--n", o->spec.n, "Number of design points to replicate (spread over the design)")->required();
    rp->add_option("--deposit-factor", o->depositFactor, "Deposit of each replicate as a share of its point's loading")->capture_default_str();
    rp->add_option("--dir", o->spec.place.dir, "Where campaigns live")->capture_default_str();
    rp->add_flag("--json", o->json, "Print JSON");
    rp->callback([&action, o] {
        action = [o] {
            const auto j = experiments::replicateCampaign(o->spec.place, o->spec.n, o->depositFactor);
            if (o->json) std::cout << j.dump(2) << '\n';
            else
                for (const auto& r : j["replicates"])
                    std::cout << "  point " << r["of_index"] << " (M = " << formatNumber(r["loading_kg"].get<double>()) << " kg) again from "
                              << formatNumber(r["initial_loading_kg"].get<double>()) << " kg\n";
            if (!o->json) std::cout << "campaign " << o->spec.place.name << ": " << j["added"] << " replicates queued (" << j["points"] << " points)\n";
            return 0;
        };
    });

    auto* rb = camp->add_subcommand(
        "rebase", "Move a mixer campaign onto a scene revision whose mesh is cell for cell its own (e.g. gcm250-v2 -> gcm250-v3 on 1 cm)");
    rb->add_option("name", o->spec.place.name, "Campaign name")->required();
    rb->add_option("--scene", o->spec.scene, "The new scene: a name in data/scenes or a .toml file")->required();
    rb->add_option("--dir", o->spec.place.dir, "Where campaigns live")->capture_default_str();
    rb->add_flag("--json", o->json, "Print JSON");
    rb->callback([&action, o] {
        action = [o] {
            const auto j = experiments::rebaseCampaign(o->spec.place, o->spec.scene);
            if (o->json) {
                std::cout << j.dump(2) << '\n';
                return 0;
            }
            std::cout << "campaign " << o->spec.place.name << ": " << j["from_scene"].get<std::string>() << " -> "
                      << j["scene"].get<std::string>() << " (" << j["mesh"].get<std::string>() << " mesh, checksum "
                      << j["mesh_checksum"].get<std::string>() << " on both), " << j["points"] << " points, "
                      << j["moved_run_dirs"].size() << " unfinished run directories moved\n";
            return 0;
        };
    });

    auto* nz = camp->add_subcommand("noise", "The finished replicate pairs and the label noise of one run they give (for surrogate fit --noise)");
    nz->add_option("name", o->spec.place.name, "Campaign name")->required();
    nz->add_option("--dir", o->spec.place.dir, "Where campaigns live")->capture_default_str();
    nz->add_flag("--json", o->json, "Print JSON");
    nz->callback([&action, o] {
        action = [o] {
            const auto j = experiments::campaignNoise(o->spec.place);
            if (o->json) {
                std::cout << j.dump(2) << '\n';
                return 0;
            }
            for (const auto& p : j["pairs"])
                std::cout << "  point " << p["index"] << ": " << formatNumber(p["loading_kg"].get<double>()) << " kg, from "
                          << formatNumber(p["initial_loading_kg"].get<double>()) << " kg"
                          << (p["laid_far_from_asked"].get<bool>()
                                  ? " (laid " + formatNumber(p["laid_kg"].get<double>()) + " kg)"
                                  : std::string())
                          << ": " << formatNumber(p["replicate_kg"].get<double>())
                          << " kg (" << formatNumber(100 * p["relative_difference"].get<double>()) << "%)"
                          << (p["two_states"].get<bool>() ? ": two steady states, not scatter (left out)" : "") << '\n';
            if (j["two_state_pairs"].get<int>() > 0)
                std::cout << j["two_state_pairs"] << " pair(s) more than " << formatNumber(experiments::kTwoStatesRatio)
                          << "x apart: the point has two steady states; the scatter below leaves them out\n";
            if (j["run_noise"].is_null()) std::cout << "no finished replicate pair in one steady state yet\n";
            else std::cout << j["n"] << " pairs: one run's scatter " << formatNumber(100 * j["run_noise"].get<double>()) << "% (surrogate fit --noise "
                           << formatNumber(j["run_noise"].get<double>()) << ")\n";
            return 0;
        };
    });

    auto* kf = camp->add_subcommand("keep-fields",
                                    "Keep every finished run's final powder fraction and velocity in <campaign dir>/fields.h5 (one mesh, a column per run), "
                                    "so that reduced models can train on them once the run directories are gone (campaign run --snapshots does "
                                    "it after each run)");
    kf->add_option("name", o->spec.place.name, "Campaign name")->required();
    kf->add_option("--dir", o->spec.place.dir, "Where campaigns live")->capture_default_str();
    kf->add_flag("--json", o->json, "Print JSON");
    kf->callback([&action, o] {
        action = [o] {
            const auto j = store::keepCampaignFields(o->spec.place.ledger(), o->spec.place.name);
            if (o->json) std::cout << j.dump(2) << '\n';
            else
                std::cout << j["kept"] << " runs' final fields in " << j["file"].get<std::string>() << " (" << j["added"] << " added)\n";
            return 0;
        };
    });

    auto* rq = camp->add_subcommand("requeue",
                                    "Give a queued or failed point its first attempt back once the cause of its failure is mended: it "
                                    "continues in its first attempt's run directory instead of starting over as a retry (no driver may run)");
    rq->add_option("name", o->spec.place.name, "Campaign name")->required();
    rq->add_option("--point", o->point, "Design point (its index)")->required();
    rq->add_option("--dir", o->spec.place.dir, "Where campaigns live")->capture_default_str();
    rq->add_flag("--json", o->json, "Print JSON");
    rq->callback([&action, o] {
        action = [o] {
            const auto j = experiments::requeuePoint(o->spec.place, o->point);
            if (o->json) std::cout << j.dump(2) << '\n';
            else
                std::cout << "campaign " << o->spec.place.name << ": point " << o->point << " queued as never tried (was "
                          << j["before"]["status"].get<std::string>() << " after " << j["before"]["attempts"] << " attempts)\n";
            return 0;
        };
    });

    auto* st = camp->add_subcommand("status", "Counts of queued, running, done and failed runs; where unfinished mixer points stand; a forecast of the core-hours left (mixer, from five steady runs)");
    st->add_option("name", o->spec.place.name, "Campaign name")->required();
    st->add_option("--dir", o->spec.place.dir, "Where campaigns live")->capture_default_str();
    st->add_option("--with-campaign", o->warmFrom,
                   "Mixer: the finished runs of this campaign (same base scene and mesh; repeatable) join the forecast's fits, "
                   "e.g. a hold-out campaign forecast from its training campaign");
    st->add_flag("--json", o->json, "Print JSON");
    st->callback([&action, o] { action = [o] { return printStatus(*o); }; });

    auto* ex = camp->add_subcommand("export", "Write every run (inputs, status, timings, results) as CSV");
    ex->add_option("name", o->spec.place.name, "Campaign name")->required();
    ex->add_option("-o,--output", o->output, "CSV file (written to a temp name, then renamed)")->required();
    ex->add_option("--dir", o->spec.place.dir, "Where campaigns live")->capture_default_str();
    ex->add_flag("--json", o->json, "Print JSON");
    ex->callback([&action, o] { action = [o] { return printExported(*o); }; });
}

}  // namespace mixload::app
