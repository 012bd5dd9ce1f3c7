// SPDX-License-Identifier: GPL-3.0-or-later
#include <cmath>
#include <cstdio>
#include <iostream>

#include "app/collapse_options.hpp"
#include "app/commands.hpp"
#include "app/mixer_options.hpp"
#include "common/atomic_file.hpp"
#include "common/process.hpp"
#include "common/clock.hpp"
#include "common/input_error.hpp"
#include "studies/collapse_study.hpp"
#include "studies/fidelity_pilot.hpp"
#include "post/verdict_replay.hpp"
#include "studies/formulation_study.hpp"
#include "studies/mixer_study.hpp"

namespace mixload::app {

namespace {
// Studies of many full runs stop the same way: at --max-hours or on SIGTERM/Ctrl-C, runs kept.
void addMaxHours(CLI::App* cmd, double& hours) {
    cmd->add_option("--max-hours", hours,
                    "Stop cleanly after this many hours (0: no limit): unfinished runs keep what they ran and the same "
                    "command resumes them; SIGTERM or Ctrl-C stops the same way")
        ->capture_default_str();
}

std::optional<std::chrono::steady_clock::time_point> studyDeadline(double hours) {
    requireRange("max-hours", hours, 0, 1e5);
    stopOnSignals();
    return deadlineAfterHours(hours);
}

struct StudyCmd {
    CollapseOptions base;
    std::vector<std::string> materials{"quartz", "copper"};
    std::vector<double> aspects{0.5, 1, 2, 3, 4, 5, 6};
    std::vector<int> cells{30};
    std::vector<std::string> rheologies{"muI"};
    std::string out = "runs/studies/collapse";
    int jobs = 2;
    bool json = false;
};

struct VerdictCmd {
    std::vector<std::string> runs;
    double tol = 0.01, flowTol = 0.03, residence = 0.5, from = -1;
    int batches = 0;
    bool json = false;
};

struct MixerStudyCmd {
    MixerOptions base;
    std::vector<std::string> methods{"mrf"};
    std::vector<std::string> meshes{"coarse"};
    std::vector<double> rpms{39};
    std::vector<double> feeds{5};
    std::vector<double> starts;         // initial loadings [kg]; empty: the base option's
    std::vector<std::string> meshers;   // empty: the scene's
    std::string out = "runs/studies/mixer";
    std::string runs;
    int jobs = 1;
    int np = 1;
    bool smFromMrf = false;
    bool smDownFeeds = false;
    double maxHours = 0;
    bool json = false;
};
struct FormulationCmd {
    MixerOptions base;
    std::string preset;
    std::vector<std::string> variants;
    std::string out = "runs/studies/formulation";
    std::string runs;
    std::string warmFrom, model;
    int jobs = 1, np = 1;
    double maxHours = 0;
    bool json = false;
};
}  // namespace

void addStudy(CLI::App& app, Action& action) {
    auto* study = app.add_subcommand("study", "Offline studies (many full runs; resumable)");
    study->require_subcommand(1);
    auto* c = study->add_subcommand(
        "collapse", "Collapse sweep over materials x rheologies x aspect ratios x meshes: table + PNG");
    auto o = std::make_shared<StudyCmd>();
    o->base.add(c);
    c->add_option("--materials", o->materials, "Materials to sweep")->capture_default_str()->delimiter(',');
    c->add_option("--aspects", o->aspects, "Aspect ratios to sweep")->capture_default_str()->delimiter(',');
    c->add_option("--meshes", o->cells, "Cells per column length to sweep")->capture_default_str()->delimiter(',');
    c->add_option("--rheologies", o->rheologies, "Rheologies to sweep")->capture_default_str()->delimiter(',');
    c->add_option("--out", o->out, "Study directory (runs are kept and reused)")->capture_default_str();
    c->add_option("--jobs", o->jobs, "Concurrent serial runs")->capture_default_str();
    c->add_flag("--json", o->json, "Print JSON");
    c->callback([&action, o] {
        action = [o] {
            experiments::CollapseStudy st;
            // Every scene is validated before the first run starts.
            for (const auto& mat : o->materials)
                for (const auto& rh : o->rheologies)
                    for (double a : o->aspects)
                        for (int n : o->cells) {
                            CollapseOptions opt = o->base;
                            opt.material = mat;
                            opt.rheology = rh;
                            opt.aspect = a;
                            opt.cellsPerLength = n;
                            st.scenes.push_back(opt.scene());
                        }
            st.out = o->out;
            st.jobs = o->jobs;
            st.progress = !o->json;
            const auto r = experiments::runCollapseStudy(st);
            if (o->json) std::cout << r.dump(2) << '\n';
            else std::cout << readFile(r["table_md"].get<std::string>()) << "plot: " << r["plot"].get<std::string>() << '\n';
            // A study with a failed run is not a finished study.
            for (const auto& row : r["rows"])
                if (row.contains("error")) return 1;
            return 0;
        };
    });

    auto* mx = study->add_subcommand(
        "mixer", "Mixer sweep over methods x meshes x rpm x feed to steady loadings: table + PNG");
    auto mo = std::make_shared<MixerStudyCmd>();
    mo->base.add(mx, /*withMethod=*/false);
    mx->add_option("--methods", mo->methods, "mrf | lts | sm")->capture_default_str()->delimiter(',');
    mx->add_option("--meshes", mo->meshes,
                   "coarse | medium | fine, or a background cell size in metres (e.g. 0.01); "
                   "ignored with --cell-size")
        ->capture_default_str()->delimiter(',');
    mx->add_option("--rpms", mo->rpms, "Impeller speeds [rev/min]")->capture_default_str()->delimiter(',');
    mx->add_option("--feeds", mo->feeds, "Feed rates [kg/h]")->capture_default_str()->delimiter(',');
    mx->add_option("--starts", mo->starts,
                   "Initial loadings to sweep [kg] (deposits; 0 = empty), instead of "
                   "--initial-loading-kg")
        ->delimiter(',');
    mx->add_option("--meshers", mo->meshers, "Meshers to sweep: ogrid | snappy (instead of --mesher)")
        ->delimiter(',');
    mx->add_option("--out", mo->out, "Study directory (runs are kept, resumed and reused)")
        ->capture_default_str();
    mx->add_option("--runs", mo->runs, "Run store shared between studies (default <out>/runs)");
    mx->add_option("--jobs", mo->jobs, "Concurrent runs")->capture_default_str();
    mx->add_option("--np", mo->np, "MPI ranks per run")->capture_default_str();
    mx->add_flag("--sm-from-mrf", mo->smFromMrf,
                 "Start each sm run from the latest fields of the MRF run at its point (run first) instead of "
                 "the deposit");
    mx->add_flag("--sm-down-feeds", mo->smDownFeeds,
                 "With --sm-from-mrf: only each speed's highest feed starts sm from MRF; each lower feed "
                 "continues the sm run at the next higher feed, at its time and mesh angle");
    addMaxHours(mx, mo->maxHours);
    mx->add_flag("--json", mo->json, "Print JSON");
    mx->callback([&action, mo] {
        action = [mo] {
            requireRange("jobs", mo->jobs, 1, 64);
            requireRange("np", mo->np, 1, 256);
            experiments::MixerStudy st;
            const std::vector<std::string> meshes =
                mo->base.cellSize ? std::vector<std::string>{""} : mo->meshes;
            // An empty entry keeps the base option (or the scene's value).
            const auto orBase = [](auto list) {
                using T = typename decltype(list)::value_type;
                std::vector<std::optional<T>> out(list.begin(), list.end());
                if (out.empty()) out.push_back(std::nullopt);
                return out;
            };
            // Every scene is validated before the first run starts.
            for (const auto& method : mo->methods)
                for (const auto& mesher : orBase(mo->meshers))
                    for (const auto& mesh : meshes)
                        for (double rpm : mo->rpms)
                            for (double feed : mo->feeds)
                                for (const auto& start : orBase(mo->starts)) {
                                    MixerOptions opt = mo->base;
                                    opt.method = method;
                                    if (mesher) opt.mesher = *mesher;
                                    if (start) opt.initialLoadingKg = *start;
                                    if (!mesh.empty()) {
                                        // An entry is a level name or a cell size in metres.
                                        if (const auto h = parseNumber(mesh)) opt.cellSize = *h;
                                        else opt.mesh = mesh;
                                    }
                                    opt.rpm = rpm;
                                    opt.feedKgH = feed;
                                    st.scenes.push_back(opt.build());
                                }
            st.out = mo->out;
            st.runs = mo->runs;
            st.jobs = mo->jobs;
            st.np = mo->np;
            st.progress = !mo->json;
            if (mo->smDownFeeds && !mo->smFromMrf)
                throw InputError("sm-down-feeds", "set", "used together with --sm-from-mrf");
            st.smFromMrf = mo->smFromMrf;
            st.smDownFeeds = mo->smDownFeeds;
            st.deadline = studyDeadline(mo->maxHours);
            const auto r = experiments::runMixerStudy(st);
            if (mo->json) std::cout << r.dump(2) << '\n';
            else std::cout << readFile(r["table_md"].get<std::string>()) << "plot: " << r["plot"].get<std::string>()
                           << "\nM(t) of every run: " << r["histories_plot"].get<std::string>() << '\n';
            if (r["unfinished"].get<size_t>() > 0 && !mo->json)
                std::cout << r["unfinished"].get<size_t>() << " of the runs are not finished; the same command resumes them\n";
            for (const auto& row : r["rows"])
                if (row.contains("error")) return 1;
            return 0;
        };
    });

    auto* fp = study->add_subcommand(
        "fidelity", "Multi-fidelity pilot: the same formulation study on two meshes, paired variant by variant: "
                    "M_fine against M_coarse, r^2, and whether co-kriging would earn its place (issue 16)");
    auto fid = std::make_shared<std::array<std::string, 3>>();
    (*fid)[2] = "runs/studies/fidelity";
    auto fjson = std::make_shared<bool>(false);
    fp->add_option("--fine", (*fid)[0], "Formulation study directory on the fine mesh, or a campaign directory (<dir>/NAME)")->required();
    fp->add_option("--coarse", (*fid)[1], "The same study (or the same design as a campaign) on the coarse mesh")->required();
    fp->add_option("--out", (*fid)[2], "Directory for fidelity.md, .csv and .png")->capture_default_str();
    fp->add_flag("--json", *fjson, "Print JSON");
    fp->callback([&action, fid, fjson] {
        action = [fid, fjson] {
            const auto r = experiments::fidelityPilot((*fid)[0], (*fid)[1], (*fid)[2]);
            if (*fjson) {
                std::cout << r.dump(2) << '\n';
                return 0;
            }
            std::cout << r["pairs"] << " pairs steady on both meshes";
            if (r.contains("fit"))
                std::cout << ": M_fine = " << r["fit"]["slope"].get<double>() << " M_coarse + " << r["fit"]["intercept_kg"].get<double>()
                          << " kg, r^2 = " << r["fit"]["r2"].get<double>() << ", ratio " << r["ratio"]["mean"].get<double>() << " +- "
                          << r["ratio"]["std"].get<double>();
            std::cout << "\n  verdict: " << r["verdict"].get<std::string>() << "\n  table " << r["table"].get<std::string>() << '\n';
            return 0;
        };
    });

    auto* v = study->add_subcommand(
        "verdict", "Replay finished mixer runs' histories through the window and the balance steady "
                   "tests: where each would have stopped, with which loading, against the history's end");
    auto vo = std::make_shared<VerdictCmd>();
    v->add_option("runs", vo->runs, "Mixer run directories")->required();
    v->add_option("--steady-tol", vo->tol, "Tolerance of both tests")->capture_default_str();
    v->add_option("--steady-flow-tol", vo->flowTol, "Outflow tolerance of both tests")
        ->capture_default_str();
    v->add_option("--steady-window-residence", vo->residence,
                  "Window test: windows of at least this share of the residence time M/feed")
        ->capture_default_str();
    v->add_option("--batches", vo->batches,
                  "Also the long-time mean: this many equal batches from --from to the end, their mean and its "
                  "Student-t 95% interval (for loadings that surge rather than settle; a residence time or more "
                  "per batch)");
    v->add_option("--from", vo->from,
                  "Start of the long-time mean [s] (default: the window test's verdict, else half the history)");
    v->add_flag("--json", vo->json, "Print JSON");
    v->callback([&action, vo] {
        action = [vo] {
            requireRange("steady-tol", vo->tol, 0.0, 0.5, false, true);
            requireRange("steady-flow-tol", vo->flowTol, 0.0, 1.0, false, true);
            requireRange("steady-window-residence", vo->residence, 0.0, 10.0);
            if (vo->batches != 0) requireRange("batches", vo->batches, 2, 1000);
            if (vo->from != -1) requireRange("from", vo->from, 0.0, 1e9);
            const auto out = post::replayAll(vo->runs, vo->tol, vo->flowTol, vo->residence, vo->batches, vo->from);
            const auto& rows = out["runs"];
            if (vo->json) {
                std::cout << out.dump(2) << '\n';
                return 0;
            }
            std::printf("%-8s %-8s %8s %10s | %-22s | %-22s\n", "rpm", "feed", "end [s]",
                        "final [kg]", "windows: t [s], dM", "balance: t [s], dM");
            for (const auto& r : rows) {
                auto cell = [&](const char* k) {
                    char b[64];
                    if (r[k].is_null()) return std::string("not reached");
                    std::snprintf(b, sizeof b, "%7.2f, %+6.2f%%", r[k]["time_s"].get<double>(),
                                  100 * r[k]["error_vs_final"].get<double>());
                    return std::string(b);
                };
                std::printf("%-8g %-8g %8.2f %10.5f | %-22s | %-22s  %s\n", r["rpm"].get<double>(),
                            r["feed_kg_h"].get<double>(), r["end_time_s"].get<double>(),
                            r["final_loading_kg"].get<double>(), cell("windows").c_str(),
                            cell("balance").c_str(), r["run_dir"].get<std::string>().c_str());
                if (r.contains("long_time")) {
                    const auto& l = r["long_time"];
                    std::printf("  long-time mean from %.1f s, %d batches of %.1f s: %.5f +- %.5f kg (95%%)\n",
                                l["from_s"].get<double>(), l["batches"].get<int>(), l["batch_s"].get<double>(),
                                l["mean_kg"].get<double>(), l["half_width_95_kg"].get<double>());
                }
            }
            std::printf("balance verdicts %d, of which false steady (off the final loading by more "
                        "than %g%%) %d, earlier than the window test %d\n",
                        out["balance_verdicts"].get<int>(), 100 * vo->tol,
                        out["balance_false_steady"].get<int>(),
                        out["balance_earlier_than_windows"].get<int>());
            return 0;
        };
    });

    auto* fm = study->add_subcommand(
        "formulation",
        "Formulation changes against a reference as full runs, each compared with the paper (its "
        "what-ifs and the signs of its Fig. 7): table + PNG, pass or fail with the number");
    auto fo = std::make_shared<FormulationCmd>();
    fo->base.add(fm);
    fm->add_option("--preset", fo->preset,
                   "paper-whatifs | fig7-signs (each parameter at 0.8 and 1.2) | fig7 (six factors per parameter, 0.7-1.3, as the paper) | "
                   "fig7-similar (fig7 without I0's runs: I0 x f is d x 1/f by the d/I0 similarity, so the d runs draw its panel) | "
                   "all (default when no --variant is given)");
    fm->add_option("--variant", fo->variants,
                   "NAME:KEY=FACTOR[,KEY=FACTOR...], KEY one of mu_s, mu_d, i0, d, rho (bulk density); "
                   "repeatable");
    fm->add_option("--out", fo->out, "Study directory (runs are kept, resumed and reused)")->capture_default_str();
    fm->add_option("--runs", fo->runs, "Run store shared between studies (default <out>/runs)");
    fm->add_option("--jobs", fo->jobs, "Concurrent runs")->capture_default_str();
    fm->add_option("--np", fo->np, "MPI ranks per run")->capture_default_str();
    fm->add_option("--warm-from", fo->warmFrom,
                   "Start every run from this mixer run directory's latest fields (e.g. a converged reference) "
                   "instead of the scene's deposit");
    addMaxHours(fm, fo->maxHours);
    fm->add_option("--model", fo->model,
                   "Also draw this surrogate's Fig. 7 curves beside the full runs' (e.g. data/models/mixer-loading-kriging.json; "
                   "drawn even before the reference is steady)");
    fm->add_flag("--json", fo->json, "Print JSON");
    fm->callback([&action, fo] {
        action = [fo] {
            requireRange("jobs", fo->jobs, 1, 64);
            requireRange("np", fo->np, 1, 256);
            experiments::FormulationStudy st;
            st.reference = fo->base.build();
            // A preset's factor outside the valid range at this reference is not run (the table
            // says why); a --variant the user wrote is refused by runFormulationStudy before any run.
            if (!fo->preset.empty() || fo->variants.empty())
                st.variants = experiments::formulationPreset(fo->preset.empty() ? "all" : fo->preset, st.reference, st.skipped);
            for (const auto& v : fo->variants) st.variants.push_back(experiments::parseFormulationVariant(v));
            st.out = fo->out;
            st.runs = fo->runs;
            st.jobs = fo->jobs;
            st.np = fo->np;
            st.warmFrom = fo->warmFrom;
            if (!fo->model.empty()) {
                st.model = surrogates::Surrogate::load(fo->model);  // refused before any run
                st.modelPath = fo->model;
            }
            st.progress = !fo->json;
            st.deadline = studyDeadline(fo->maxHours);
            const auto r = experiments::runFormulationStudy(st);
            if (fo->json) std::cout << r.dump(2) << '\n';
            else std::cout << readFile(r["table_md"].get<std::string>()) << "plot: " << r["plot"].get<std::string>() << '\n';
            if (r["unfinished"].get<size_t>() > 0 && !fo->json)
                std::cout << r["unfinished"].get<size_t>() << " of the runs are not finished; the same command resumes them\n";
            for (const auto& row : r["rows"])
                if (row.contains("error")) return 1;
            return r["reference"].contains("error") ? 1 : 0;
        };
    });
}

}  // namespace mixload::app
