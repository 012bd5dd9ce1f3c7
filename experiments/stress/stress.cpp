// SPDX-License-Identifier: GPL-3.0-or-later
#include "stress/stress.hpp"

#include <sys/mount.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <map>
#include <chrono>
#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "common/process.hpp"
#include "common/progress.hpp"
#include "mixload_version.hpp"
#include "scene/material.hpp"

namespace mixload::experiments {

namespace fs = std::filesystem;

namespace {

nlohmann::json parsedOut(const StressOutcome& o) {
    try {
        return nlohmann::json::parse(o.out);
    } catch (const std::exception&) {
        return nullptr;
    }
}

bool finite(const nlohmann::json& j, const char* key) {
    return j.contains(key) && j[key].is_number() && std::isfinite(j[key].get<double>());
}

// A collapse's own checks: powder conserved, a physical deposit.
std::string collapseChecks(const StressOutcome& o, const fs::path&) {
    const auto j = parsedOut(o);
    if (j.is_null()) return "exit 0 without a JSON result";
    if (!finite(j, "runout_star") || !finite(j, "height_star") || !finite(j, "powder_mass_error"))
        return "result without finite runout, height and mass error";
    if (std::abs(j["powder_mass_error"].get<double>()) > 1e-3)
        return "powder volume changed by " + formatNumber(j["powder_mass_error"].get<double>());
    const double h = j["height_star"].get<double>();
    if (!(h > 0 && h <= 1.05)) return "final height H*f = " + formatNumber(h) + " outside (0, 1.05]";
    if (j["runout_star"].get<double>() < -0.05) return "negative runout";
    return "";
}

// A mixer's own checks: the powder balance the result reports, a physical loading.
std::string mixerChecks(const StressOutcome& o, const fs::path&) {
    const auto j = parsedOut(o);
    if (j.is_null()) return "exit 0 without a JSON result";
    if (!finite(j, "loading_kg") || j["loading_kg"].get<double>() < 0) return "loading missing, not finite or negative";
    if (!j.value("powder_balance_ok", false)) return "powder balance not closed (powder_balance_ok false) but exit 0";
    return "";
}

// A prediction's own checks: M and its interval physical (M >= 0).
std::string predictChecks(const StressOutcome& o, const fs::path&) {
    const auto j = parsedOut(o);
    if (j.is_null()) return "exit 0 without a JSON result";
    const auto& p = j.is_array() ? j[0] : j;
    if (!finite(p, "loading_kg") || p["loading_kg"].get<double>() < 0) return "loading missing or negative";
    if (p.contains("ci95_kg") && p["ci95_kg"][0].get<double>() < 0) return "interval below zero";
    return "";
}

std::string truncateFile(const fs::path& f) {
    if (!fs::exists(f)) return "the step before did not write " + f.string();
    fs::resize_file(f, fs::file_size(f) / 2);
    return "";
}

// base with each "--key value" pair of extra set: replaced where base has the key, else appended.
std::vector<std::string> withOptions(std::vector<std::string> base, const std::vector<std::string>& extra) {
    for (size_t i = 0; i < extra.size(); ++i) {
        const bool valued = i + 1 < extra.size() && extra[i + 1].rfind("--", 0) != 0;
        const auto at = std::find(base.begin(), base.end(), extra[i]);
        if (at == base.end()) {
            base.push_back(extra[i]);
            if (valued) base.push_back(extra[i + 1]);
        } else if (valued) {
            *(at + 1) = extra[i + 1];
        }
        if (valued) ++i;
    }
    return base;
}

// The check of a case that must end in a clear error: a result there is the failure named.
std::function<std::string(const StressOutcome&, const fs::path&)> mustRefuse(const std::string& failure) {
    return [failure](const StressOutcome&, const fs::path&) { return failure; };
}

StressCase collapseCase(const std::string& group, const std::string& name, const std::string& tries,
                        std::vector<std::string> extra) {
    const auto args = withOptions({"collapse", "--material", "quartz", "--cells-per-length", "8", "--aspect", "1",
                                   "--out", "{dir}/run", "--json"},
                                  extra);
    StressCase c{group, name, tries, true, {{args}}, {}, {}, collapseChecks, {}};
    return c;
}

StressCase mixerCase(const std::string& group, const std::string& name, const std::string& tries,
                     std::vector<std::string> extra) {
    const auto args = withOptions({"mixer", "--scene", "gcm250-v2", "--cell-size", "0.02", "--end-time", "0.3",
                                   "--out", "{dir}/run", "--json"},
                                  extra);
    return StressCase{group, name, tries, false, {{args}}, {}, {}, mixerChecks, {}};
}

StressCase predictCase(const std::string& name, const std::string& tries, std::vector<std::string> extra) {
    // The paper's reference point (Avicel, 39 rpm, 5 kg/h), one input moved.
    const auto args = withOptions({"predict", "--mu-s", "0.31", "--mu-d", "0.44", "--i0", "0.28", "--d", "240e-6",
                                   "--rho", "330", "--feed-kg-h", "5", "--rpm", "39", "--json"},
                                  extra);
    return StressCase{"surrogates", name, tries, true, {{args}}, {}, {}, predictChecks, {}};
}

}  // namespace

std::vector<StressCase> stressCases() {
    std::vector<StressCase> cs;
    // Rheology: coefficient sets at and beyond the edges of what the model is meant for.
    cs.push_back(collapseCase("rheology", "paper-quartz-standard",
                              "the paper's quartz fit read in the standard convention: no well-posed window", {}));
    cs.push_back(collapseCase("rheology", "i0-0.01", "I0 = 0.01", {"--i0", "0.01"}));
    cs.push_back(collapseCase("rheology", "mu_s-0.1", "mu_s = 0.1 (mu_d 0.4)", {"--mu-s", "0.1", "--mu-d", "0.4"}));
    cs.push_back(collapseCase("rheology", "mu_s-1.3", "mu_s = 1.3 (mu_d 1.6)", {"--mu-s", "1.3", "--mu-d", "1.6"}));
    cs.push_back(collapseCase("rheology", "dmu-0.01", "delta mu = 0.01", {"--mu-s", "0.5", "--mu-d", "0.51"}));
    cs.push_back(collapseCase("rheology", "dmu-1.0", "delta mu = 1.0", {"--mu-s", "0.5", "--mu-d", "1.5"}));
    cs.push_back(collapseCase("rheology", "muIRegularised", "Barker & Gray's regularised law", {"--rheology", "muIRegularised"}));
    cs.push_back(collapseCase("rheology", "schaeffer", "constant friction (Schaeffer)", {"--rheology", "schaeffer"}));
    cs.push_back(collapseCase("rheology", "mu_d-below-mu_s", "mu_d < mu_s (must be refused)", {"--mu-s", "0.6", "--mu-d", "0.4"}));
    // Numerics.
    cs.push_back(collapseCase("numerics", "courant-0.25", "Courant limit 0.25", {"--max-courant", "0.25"}));
    cs.push_back(collapseCase("numerics", "courant-4", "Courant limit 4", {"--max-courant", "4"}));
    cs.push_back(collapseCase("numerics", "np-2", "two MPI ranks", {"--np", "2"}));
    cs.push_back(collapseCase("numerics", "mesh-4-cells", "the coarsest mesh the scene accepts, Li/4",
                              {"--cells-per-length", "4"}));
    // Operation: tiny mixer runs (full tier).
    for (const char* rpm : {"0", "1", "500"})
        cs.push_back(mixerCase("operation", std::string("rpm-") + rpm, std::string("rpm ") + rpm, {"--rpm", rpm}));
    for (const char* feed : {"0", "0.5", "200"})
        cs.push_back(mixerCase("operation", std::string("feed-") + feed, std::string("feed ") + feed + " kg/h",
                               {"--feed-kg-h", feed}));
    for (const char* rho : {"100", "2000"})
        cs.push_back(mixerCase("operation", std::string("rho-") + rho, std::string("bulk density ") + rho + " kg/m3",
                               {"--rho", rho}));
    {
        auto c = mixerCase("operation", "overfill", "a deposit of 50 kg, more than the barrel holds",
                           {"--initial-loading-kg", "50"});
        c.quick = true;  // refused before any run: cheap
        cs.push_back(c);
    }
    cs.push_back(mixerCase("numerics", "mixer-np-2", "the tiny mixer on two MPI ranks", {"--np", "2"}));
    // The sliding mesh: its per-fragment AMI transport must conserve powder (the checks' balance),
    // also with the rotor at 500 rpm; it runs serially and must refuse two ranks before any run.
    cs.push_back(mixerCase("numerics", "sm", "the sliding mesh", {"--method", "sm"}));
    cs.push_back(mixerCase("numerics", "sm-rpm-500", "the sliding mesh at 500 rpm", {"--method", "sm", "--rpm", "500"}));
    {
        auto c = mixerCase("numerics", "sm-np-2", "the sliding mesh on two MPI ranks (serial only)",
                           {"--method", "sm", "--np", "2"});
        c.quick = true;
        c.check = mustRefuse("the sliding mesh ran on two ranks");
        cs.push_back(c);
    }
    // Faults.
    {
        StressCase c = collapseCase("faults", "killed-mid-run", "the run killed (SIGKILL) after 3 s, then run again",
                                    {"--cells-per-length", "12", "--aspect", "2"});
        c.steps.insert(c.steps.begin(), StressStep{c.steps[0].args, 3.0, false});
        c.check = [](const StressOutcome& o, const fs::path& dir) {
            const std::string s = collapseChecks(o, dir);
            if (!s.empty()) return s;
            return parsedOut(o).value("resumed", false) ? std::string() : std::string("the second call did not resume");
        };
        cs.push_back(c);
    }
    {
        StressCase c{"faults", "corrupted-snapshot", "a snapshot file cut to half its size, then read", true,
                     {{{"collapse", "--material", "quartz", "--cells-per-length", "8", "--aspect", "1", "--out",
                        "{dir}/run", "--snapshots", "--json"}},
                      {{"snapshots", "info", "{dir}/run/snapshots.h5", "--json"}}},
                     {},
                     [](const fs::path& dir, size_t) { return truncateFile(dir / "run" / "snapshots.h5"); },
                     mustRefuse("a truncated snapshot read as fine"),
                     {}};
        cs.push_back(c);
    }
    {
        StressCase c{"faults", "truncated-ledger", "a campaign ledger cut to half its size, then read", true,
                     {{{"campaign", "create", "c", "--ranges", "{data}/campaigns/mixer-v2-ranges.toml", "--n", "4",
                        "--dir", "{dir}"}},
                      {{"campaign", "status", "c", "--dir", "{dir}", "--json"}}},
                     {},
                     [](const fs::path& dir, size_t) { return truncateFile(dir / "c" / "ledger.sqlite"); },
                     mustRefuse("a truncated ledger read as fine"),
                     {}};
        cs.push_back(c);
    }
    {
        StressCase c{"faults", "model-other-version", "a surrogate model file of schema version 99", true,
                     {{withOptions({"predict", "--mu-s", "0.31", "--mu-d", "0.44", "--i0", "0.28", "--d", "240e-6",
                                    "--rho", "330", "--feed-kg-h", "5", "--rpm", "39", "--json"},
                                   {"--model", "{dir}/model.json"})}},
                     [](const fs::path& dir) {
                         auto j = nlohmann::json::parse(readFile(scene::dataDir() / "models" / "mixer-loading-kriging.json"));
                         if (!j.contains("schema_version")) return std::string("the shipped model has no schema_version");
                         j["schema_version"] = 99;
                         writeFileAtomic(dir / "model.json", j.dump());
                         return std::string();
                     },
                     {},
                     mustRefuse("a model of another version used"),
                     {}};
        cs.push_back(c);
    }
    {
        StressCase c{"faults", "two-drivers", "a second `campaign run` on a campaign whose driver is running", true,
                     {{{"campaign", "create", "c", "--ranges", "{data}/campaigns/mixer-v2-ranges.toml", "--n", "2",
                        "--cell-size", "0.02", "--end-time", "0.2", "--dir", "{dir}"}},
                      {{"campaign", "run", "c", "--dir", "{dir}", "--json"}, 25.0, true},
                      {{"campaign", "run", "c", "--dir", "{dir}", "--json"}}},
                     {},
                     {},
                     mustRefuse("two drivers ran one campaign"),
                     {}};
        cs.push_back(c);
    }
    {
        // The disk fills while the run writes: a small tmpfs (needs root and mount rights).
        StressCase c = collapseCase("faults", "disk-full", "the run's disk full (a 1 MB tmpfs)",
                                    {"--out", "{dir}/full/run"});
        c.setup = [](const fs::path& dir) {
            fs::create_directories(dir / "full");
            if (::mount("tmpfs", (dir / "full").c_str(), "tmpfs", 0, "size=1m") != 0)
                return std::string("cannot mount a tmpfs here (") + std::strerror(errno) + ")";
            return std::string();
        };
        c.teardown = [](const fs::path& dir) { ::umount((dir / "full").c_str()); };
        // Success on a full disk would be a surprise; the collapse's own checks then judge it.
        cs.push_back(c);
    }
    // The reduced model far outside its training runs: a POD-Galerkin collapse model built on one
    // run of quartz, asked for mu_s 3 (staging: the run, its float64 snapshots, the model).
    {
        StressCase c{"surrogates", "rom-far-outside", "the POD-Galerkin model at mu_s 3, trained on mu_s 1.33 (must be refused)", true,
                     {{{"collapse", "--material", "quartz", "--cells-per-length", "8", "--aspect", "2", "--writes-per-tstar",
                        "20", "--out", "{dir}/run", "--json"}},
                      {{"snapshots", "export", "{dir}/run", "-o", "{dir}/s.h5", "--fields", "alpha,U,p,phi", "--float64"}},
                      {{"rom", "build", "{dir}/s.h5", "-o", "{dir}/m.h5", "--modes", "4"}},
                      {{"rom", "run", "{dir}/m.h5", "--mu-s", "3", "--mu-d", "3.5", "--i0", "0.3", "--json"}}},
                     {},
                     {},
                     mustRefuse("answered far outside its training"),
                     {}};
        cs.push_back(c);
    }
    // Surrogates far outside their box.
    cs.push_back(predictCase("feed-500", "feed 500 kg/h, trained up to 45 (must be refused)", {"--feed-kg-h", "500"}));
    cs.push_back(predictCase("feed-500-extrapolate", "feed 500 kg/h with --extrapolate: M and interval >= 0",
                             {"--feed-kg-h", "500", "--extrapolate"}));
    cs.push_back(predictCase("rpm-0", "rpm 0", {"--rpm", "0"}));
    cs.push_back(predictCase("rho-negative", "bulk density -300", {"--rho", "-300"}));
    return cs;
}

std::pair<std::string, std::string> classifyStress(const StressOutcome& o, const std::string& checkFailure) {
    if (o.rc == 0) {
        if (checkFailure.empty()) return {"result", ""};
        return {"silent-failure", "exit 0 but " + checkFailure};
    }
    if (o.rc == 1 || o.rc == 2) {
        // A clear error: a message on stderr (mixload's own, or the option parser's).
        const auto at = o.err.find("mixload:");
        const auto first = at != std::string::npos ? at : o.err.find_first_not_of(" \n");
        if (first != std::string::npos) {
            std::string msg = o.err.substr(first);
            return {"clear-error", msg.substr(0, msg.find('\n'))};
        }
        return {"silent-failure", "exit " + std::to_string(o.rc) + " without a message"};
    }
    return {"silent-failure", "crashed (exit " + std::to_string(o.rc) + ")"};
}

namespace {

std::string expand(const std::string& a, const fs::path& dir) {
    std::string s = a;
    for (const auto& [key, value] : {std::pair<std::string, std::string>{"{dir}", dir.string()},
                                     {"{data}", scene::dataDir().string()}})
        for (size_t p; (p = s.find(key)) != std::string::npos;) s.replace(p, key.size(), value);
    return s;
}

StressOutcome runStep(const fs::path& exe, const StressStep& st, const fs::path& dir, int index) {
    const fs::path err = dir / ("stderr-" + std::to_string(index) + ".txt");
    std::vector<std::string> argv;
    if (st.killAfterSeconds > 0) argv = {"timeout", "-s", "KILL", formatNumber(st.killAfterSeconds)};
    argv.push_back(exe.string());
    for (const auto& a : st.args) argv.push_back(expand(a, dir));
    // stderr to a file, stdout line by line: the two must not interleave.
    std::string cmd = "exec \"$0\"";
    for (size_t i = 1; i < argv.size(); ++i) cmd += " \"${" + std::to_string(i) + "}\"";
    cmd += " 2>\"" + err.string() + "\"";
    ProcessSpec spec;
    spec.argv = {"sh", "-c", cmd};
    spec.argv.insert(spec.argv.end(), argv.begin(), argv.end());
    StressOutcome o;
    spec.onLine = [&](const std::string& l) { o.out += l + "\n"; };
    const auto t0 = std::chrono::steady_clock::now();
    o.rc = runProcess(spec);
    o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    o.err = fs::exists(err) ? readFile(err) : "";
    return o;
}

}  // namespace

nlohmann::json runStress(const StressOptions& o) {
    std::vector<StressCase> cases;
    for (auto& c : stressCases())
        if ((o.full || c.quick) && (o.only.empty() || std::count(o.only.begin(), o.only.end(), c.group)))
            cases.push_back(c);
    fs::create_directories(o.out);
    nlohmann::json rows = nlohmann::json::array();
    std::map<std::string, int> counts{{"result", 0}, {"clear-error", 0}, {"skipped", 0}, {"silent-failure", 0}};
    Progress bar("stress", o.progress);
    for (size_t k = 0; k < cases.size(); ++k) {
        const auto& c = cases[k];
        const fs::path dir = fs::absolute(o.out / (c.group + "-" + c.name));
        fs::remove_all(dir);
        fs::create_directories(dir);
        std::string klass, why;
        StressOutcome last;
        double seconds = 0;
        const std::string skip = c.setup ? c.setup(dir) : "";
        if (!skip.empty()) {
            klass = "skipped", why = skip;
        } else {
            std::thread background;
            for (size_t i = 0; i < c.steps.size() && klass.empty(); ++i) {
                if (i > 0 && c.between) {
                    const std::string s = c.between(dir, i);
                    if (!s.empty()) klass = "skipped", why = s;
                    if (!klass.empty()) break;
                }
                if (c.steps[i].background) {
                    // Only the judged step's outcome counts; this one is there to hold the campaign.
                    background = std::thread([&, i] { runStep(o.exe, c.steps[i], dir, static_cast<int>(i)); });
                    // Until the first driver holds the campaign (its first run directory appears).
                    for (int w = 0; w < 600 && !fs::exists(dir / "c" / "runs"); ++w)
                        std::this_thread::sleep_for(std::chrono::milliseconds(100));
                    continue;
                }
                last = runStep(o.exe, c.steps[i], dir, static_cast<int>(i));
                seconds += last.seconds;
                // A step before the judged one that was meant to finish must have: otherwise the
                // case did not stage what it tries.
                if (i + 1 < c.steps.size() && c.steps[i].killAfterSeconds == 0 && last.rc != 0)
                    klass = "skipped", why = "staging step failed: " + classifyStress(last, "").second;
            }
            if (background.joinable()) background.join();
            if (klass.empty()) {
                const std::string failure = last.rc == 0 && c.check ? c.check(last, dir) : "";
                std::tie(klass, why) = classifyStress(last, failure);
            }
        }
        if (c.teardown) c.teardown(dir);
        ++counts[klass];
        rows.push_back({{"group", c.group}, {"case", c.name}, {"tries", c.tries}, {"class", klass}, {"why", why},
                        {"exit", last.rc}, {"seconds", seconds}, {"dir", dir.string()}});
        bar.update(double(k + 1) / cases.size(), c.group + "/" + c.name + ": " + klass);
    }
    bar.finish();
    nlohmann::json report{{"cases", cases.size()},
                          {"results", counts["result"]},
                          {"clear_errors", counts["clear-error"]},
                          {"skipped", counts["skipped"]},
                          {"silent_failures", counts["silent-failure"]},
                          {"tier", o.full ? "full" : "quick"},
                          {"rows", rows},
                          {"mixload_version", kVersion},
                          {"git_commit", kGitCommit}};
    std::ostringstream md, csv;
    md << "# mixload stress (" << report["tier"].get<std::string>() << " tier)\n\n" << cases.size() << " cases: "
       << counts["result"] << " results whose checks pass, " << counts["clear-error"] << " clear errors, "
       << counts["skipped"] << " skipped, **" << counts["silent-failure"] << " silent failures**; mixload "
       << kVersion << " (" << kGitCommit << ")\n\n| group | case | tries | outcome | exit | s | message / why |\n"
       << "|---|---|---|---|---|---|---|\n";
    csv << "group,case,class,exit,seconds\n";
    for (const auto& r : rows) {
        md << "| " << r["group"].get<std::string>() << " | " << r["case"].get<std::string>() << " | "
           << r["tries"].get<std::string>() << " | " << r["class"].get<std::string>() << " | " << r["exit"] << " | "
           << formatNumber(std::round(r["seconds"].get<double>() * 10) / 10) << " | " << r["why"].get<std::string>()
           << " |\n";
        csv << r["group"].get<std::string>() << ',' << r["case"].get<std::string>() << ',' << r["class"].get<std::string>()
            << ',' << r["exit"] << ',' << r["seconds"].get<double>() << '\n';
    }
    writeFileAtomic(o.out / "stress.md", md.str());
    writeFileAtomic(o.out / "stress.csv", csv.str());
    writeFileAtomic(o.out / "stress.json", report.dump(2));
    report["table_md"] = (o.out / "stress.md").string();
    return report;
}

}  // namespace mixload::experiments
