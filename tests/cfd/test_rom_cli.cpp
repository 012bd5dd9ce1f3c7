// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload rom pod` on the snapshots of tiny real collapses: the basis file reproduces every stored
// snapshot with all modes, its left-out energy is the projection error with fewer, and snapshots of
// another mesh, bad options and unknown fields are refused with nothing written.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "rom/pod/pod_model.hpp"
#include "store/campaign_fields.hpp"
#include "store/snapshot_file.hpp"

using namespace mixload;
using namespace mixload::testing;
namespace fs = std::filesystem;

namespace {
fs::path collapseSnapshots(const std::string& name, const std::string& cells) {
    const fs::path out = scratchDir("rom-" + name) / "run";
    const auto r = runMixload({"collapse", "--material", "quartz", "--aspect", "2", "--cells-per-length", cells,
                               "--out", out.string(), "--snapshots", "--json"});
    EXPECT_EQ(r.rc, 0) << r.err;
    return out / "snapshots.h5";
}
// A campaign NAME in dir over the ranges given (TOML text), created with `create` options and run with
// snapshots kept.
void snapshotCampaign(const fs::path& dir, const std::string& name, const std::string& ranges,
                      const std::vector<std::string>& create) {
    std::ofstream(dir / (name + ".toml")) << ranges;
    std::vector<std::string> args{"campaign", "create", name, "--ranges", (dir / (name + ".toml")).string(), "--dir", dir.string()};
    args.insert(args.end(), create.begin(), create.end());
    auto r = runMixload(args);
    ASSERT_EQ(r.rc, 0) << r.err;
    r = runMixload({"campaign", "run", name, "--snapshots", "--dir", dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
}
}  // namespace

TEST(RomPod, BasisFileReproducesTheStoredSnapshots) {
    const fs::path h5 = collapseSnapshots("pod", "8");
    const fs::path dir = scratchDir("rom-pod-out");
    const auto r = runMixload({"rom", "pod", h5.string(), "--field", "alpha", "--field", "U", "--energy", "1",
                               "-o", (dir / "full.h5").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_TRUE(fs::exists(j["spectrum_png"].get<std::string>()));
    const auto m = rom::readPod(dir / "full.h5");
    const store::SnapshotFile f(h5);
    EXPECT_EQ(m.meshFingerprint, f.meshFingerprint());
    EXPECT_EQ(m.components, (std::vector<int>{1, 3}));
    EXPECT_LT(m.basis.orthonormalityError(), 1e-10);
    const Eigen::MatrixXd x = rom::stackedFields(f, m.fields);
    ASSERT_EQ(static_cast<size_t>(x.cols()), m.basis.snapshots);
    for (Eigen::Index t = 0; t < x.cols(); ++t) {
        const Eigen::VectorXd u = x.col(t);
        EXPECT_LT((m.basis.reconstruct(m.basis.project(u)) - u).norm(), 1e-8 * u.norm()) << "time " << t;
    }

    // Five modes: what they leave out of the snapshots is the energy of the modes dropped.
    ASSERT_EQ(runMixload({"rom", "pod", h5.string(), "--field", "alpha", "--modes", "5", "-o",
                          (dir / "five.h5").string()})
                  .rc,
              0);
    const auto five = rom::readPod(dir / "five.h5");
    ASSERT_EQ(five.basis.modes.cols(), 5);
    const Eigen::MatrixXd a = f.matrix("alpha");
    double err = 0;
    for (Eigen::Index t = 0; t < a.cols(); ++t) {
        const Eigen::VectorXd e = a.col(t) - five.basis.reconstruct(five.basis.project(a.col(t)));
        err += e.cwiseProduct(e).dot(five.basis.weights);
    }
    const auto& l = five.basis.eigenvalues;
    EXPECT_NEAR(err, l.tail(l.size() - 5).sum(), 1e-9 * l.sum());
}

TEST(RomPod, RefusesMixedMeshesBadOptionsAndUnknownFields) {
    const fs::path a = collapseSnapshots("mesh8", "8"), b = collapseSnapshots("mesh6", "6");
    const fs::path out = scratchDir("rom-pod-bad") / "basis.h5";
    const auto refused = [&](std::vector<std::string> args, const std::string& needle) {
        args.insert(args.begin(), {"rom", "pod"});
        args.insert(args.end(), {"-o", out.string()});
        const auto r = runMixload(args);
        EXPECT_EQ(r.rc, 2) << r.out << r.err;
        EXPECT_NE(r.err.find(needle), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(out));
    };
    refused({a.string(), b.string()}, "invalid snapshots = " + b.string());
    refused({a.string(), "--energy", "0"}, "invalid energy = 0");
    refused({a.string(), "--field", "T"}, "invalid field = T");
    refused({a.string(), "--campaign", "c1"}, "not both");
    refused({}, "invalid FILES");
    refused({(a.parent_path() / "nothing.h5").string()}, "no such file");
}

TEST(RomDeim, ViscosityOfARealCollapseIsExactAtFullRankAndReportsItsHoldOut) {
    const fs::path h5 = collapseSnapshots("deim", "8");
    const store::SnapshotFile f(h5);
    const size_t train = (f.times().size() + 1) / 2;
    const fs::path png = h5.parent_path() / "deim.png";
    auto r = runMixload({"rom", "deim", h5.string(), "--modes", std::to_string(train), "--plot", png.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["train_snapshots"], train);
    EXPECT_EQ(j["holdout_snapshots"], f.times().size() - train);
    const auto& rows = j["by_modes"];
    ASSERT_EQ(rows.size(), train);
    // As many points as training snapshots: those are reproduced to round-off.
    EXPECT_LT(rows.back()["train"]["max"].get<double>(), 1e-8);
    // Held-out times are not; the error is reported, whatever it is, and falls with more points.
    EXPECT_GT(rows.back()["holdout"]["mean"].get<double>(), 0.0);
    EXPECT_LT(rows.back()["holdout"]["mean"].get<double>(), rows.front()["holdout"]["mean"].get<double>());
    EXPECT_EQ(rows.back()["points"].size(), train);
    EXPECT_TRUE(fs::exists(png));
    r = runMixload({"rom", "deim", h5.string(), "--modes", "0"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("invalid modes = 0"), std::string::npos) << r.err;
}

TEST(RomRegression, LeavesEachCampaignRunOutAndPredictsIt) {
    // Five tiny collapses over (mu_s, delta_mu), run by the campaign driver with snapshots.
    const fs::path dir = scratchDir("rom-regression");
    snapshotCampaign(dir, "reg",
                     "scene = \"collapse\"\n[mu_s]\nmin = 0.8\nmax = 1.3\nunit = \"1\"\n"
                     "[delta_mu]\nmin = 0.25\nmax = 0.5\nunit = \"1\"\n",
                     {"--n", "5", "--mesh", "8"});
    auto r = runMixload({"rom", "regression", "--campaign", "reg", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["runs"], 5);
    EXPECT_EQ(j["inputs"].size(), 2u);
    ASSERT_EQ(j["rows"].size(), 5u);
    std::cout << "LOO over 5 runs: L*f POD regression " << j["summary"]["runout_star"]["pod_regression_mean_abs_error"]
              << ", kriging " << j["summary"]["runout_star"]["kriging_mean_abs_error"] << ", alpha " << j["alpha_error_mean"] << '\n';
    // The stored field gives the run's own runout (the same definition as the monitor's).
    EXPECT_LT(j["summary"]["runout_star"]["stored_field_mean_abs_error"].get<double>(), 1e-3);
    // Left-out predictions from four runs: errors of a few percent, not a failed fit.
    EXPECT_LT(j["summary"]["runout_star"]["pod_regression_mean_abs_error"].get<double>(), 0.25);
    EXPECT_LT(j["alpha_error_mean"].get<double>(), 0.5);
    EXPECT_LT(j["predict_seconds"].get<double>(), 0.01);
    // Every run kept its velocity, so the regression predicts it too.
    ASSERT_FALSE(j["u_error_mean"].is_null()) << j["velocity"];
    EXPECT_GT(j["u_error_mean"].get<double>(), 0.0);
    EXPECT_TRUE(std::isfinite(j["u_error_mean"].get<double>()));
    // Fitted on all five, at a new point: the quantities and the field as a snapshot file.
    r = runMixload({"rom", "regression", "--campaign", "reg", "--dir", dir.string(), "--at", "mu_s=1.0", "--at",
                    "delta_mu=0.4", "--fields", (dir / "at.h5").string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto p = nlohmann::json::parse(r.out);
    EXPECT_GT(p["runout_star"].get<double>(), 1.0);
    EXPECT_TRUE(p["warnings"].empty());
    const store::SnapshotFile at(dir / "at.h5");
    EXPECT_EQ(at.times().size(), 1u);
    EXPECT_EQ(at.components("U"), 3);
    EXPECT_TRUE(fs::exists(dir / "at.xmf"));
    // Checked on a hold-out campaign of the same mesh, placed by its own design: every hold-out run
    // predicted by the regression and by kriging fitted on all five training runs.
    snapshotCampaign(dir, "ho",
                     "scene = \"collapse\"\n[mu_s]\nmin = 0.85\nmax = 1.25\nunit = \"1\"\n"
                     "[delta_mu]\nmin = 0.28\nmax = 0.47\nunit = \"1\"\n",
                     {"--n", "2", "--mesh", "8", "--seed", "9"});
    r = runMixload({"rom", "regression", "--campaign", "reg", "--dir", dir.string(), "--holdout", "ho", "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto ho = nlohmann::json::parse(r.out);
    EXPECT_EQ(ho["runs"], 5);
    EXPECT_EQ(ho["holdout_runs"], 2);
    ASSERT_EQ(ho["rows"].size(), 2u);
    EXPECT_LE(ho["holdout_outside_training_box"].size(), 2u);  // the runs' own box, narrower than the ranges
    const auto& hs = ho["summary"]["runout_star"];
    std::cout << "hold-out of 2 runs: L*f POD regression " << hs["pod_regression_mean_abs_error"] << " (max "
              << hs["pod_regression_max_abs_error"] << "), kriging " << hs["kriging_mean_abs_error"] << ", alpha "
              << ho["alpha_error_mean"] << ", U " << ho["u_error_mean"] << '\n';
    EXPECT_LT(hs["pod_regression_mean_abs_error"].get<double>(), 0.25);
    EXPECT_GE(hs["pod_regression_max_abs_error"].get<double>(), hs["pod_regression_mean_abs_error"].get<double>());
    EXPECT_LT(hs["stored_field_mean_abs_error"].get<double>(), 1e-3);
    EXPECT_TRUE(std::isfinite(ho["u_error_mean"].get<double>()));
    // The modes' own error bounds the regression's from below (a projection is the best fit).
    EXPECT_LE(ho["alpha_projection_error_mean"].get<double>(), ho["alpha_error_mean"].get<double>() + 1e-12);
    EXPECT_LE(ho["u_projection_error_mean"].get<double>(), ho["u_error_mean"].get<double>() + 1e-12);
    // The paired difference with kriging lies inside its own bootstrap interval.
    const double diff = hs["pod_minus_kriging_mean_abs_error"].get<double>();
    EXPECT_NEAR(diff, hs["pod_regression_mean_abs_error"].get<double>() - hs["kriging_mean_abs_error"].get<double>(), 1e-12);
    EXPECT_LE(hs["pod_minus_kriging_ci90"][0].get<double>(), diff + 1e-12);
    EXPECT_GE(hs["pod_minus_kriging_ci90"][1].get<double>(), diff - 1e-12);
    // A hold-out on another mesh is refused, naming it.
    snapshotCampaign(dir, "coarse",
                     "scene = \"collapse\"\n[mu_s]\nmin = 0.85\nmax = 1.25\nunit = \"1\"\n", {"--n", "1", "--mesh", "6"});
    r = runMixload({"rom", "regression", "--campaign", "reg", "--dir", dir.string(), "--holdout", "coarse"});
    EXPECT_EQ(r.rc, 2) << r.err;
    EXPECT_NE(r.err.find("invalid holdout = coarse"), std::string::npos) << r.err;
    // A point missing an input, or naming one the design does not vary, is refused.
    for (const auto& bad : std::vector<std::vector<std::string>>{{"--at", "mu_s=1.0"},
                                                                 {"--at", "mu_s=1.0", "--at", "delta_mu=0.4", "--at", "i0=0.3"},
                                                                 {"--at", "mu_s"}}) {
        std::vector<std::string> args{"rom", "regression", "--campaign", "reg", "--dir", dir.string()};
        args.insert(args.end(), bad.begin(), bad.end());
        const auto b = runMixload(args);
        EXPECT_EQ(b.rc, 2) << b.err;
        EXPECT_NE(b.err.find("invalid at"), std::string::npos) << b.err;
    }
    // The driver kept every run's final field beside the ledger: with the run directories gone (a
    // machine that came back without them), the regression trains on the kept fields and gives
    // the same answers.
    const fs::path kept = dir / "reg" / "fields.h5";
    ASSERT_TRUE(fs::exists(kept));
    EXPECT_EQ(store::SnapshotFile(kept).times().size(), 5u);
    fs::rename(dir / "reg" / "runs", dir / "reg" / "runs-gone");
    r = runMixload({"rom", "regression", "--campaign", "reg", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto again = nlohmann::json::parse(r.out);
    EXPECT_EQ(again["runs"], 5);
    EXPECT_DOUBLE_EQ(again["summary"]["runout_star"]["pod_regression_mean_abs_error"].get<double>(),
                     j["summary"]["runout_star"]["pod_regression_mean_abs_error"].get<double>());
    EXPECT_DOUBLE_EQ(again["alpha_error_mean"].get<double>(), j["alpha_error_mean"].get<double>());
    EXPECT_DOUBLE_EQ(again["u_error_mean"].get<double>(), j["u_error_mean"].get<double>());
    r = runMixload({"campaign", "keep-fields", "reg", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["added"], 0);
    fs::rename(dir / "reg" / "runs-gone", dir / "reg" / "runs");

    // A run that kept no velocity (exported before velocities were kept) leaves U to the others:
    // the velocity is regressed and checked on the four runs that have one.
    fs::path first;
    for (const auto& e : fs::directory_iterator(dir / "reg" / "runs"))
        if (e.is_directory() && (first.empty() || e.path() < first)) first = e.path();
    ASSERT_FALSE(first.empty());
    r = runMixload({"snapshots", "export", first.string(), "--fields", "alpha"});
    ASSERT_EQ(r.rc, 0) << r.err;
    fs::remove(kept);
    r = runMixload({"rom", "regression", "--campaign", "reg", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto partial = nlohmann::json::parse(r.out);
    EXPECT_EQ(partial["u_error_runs"], 4);
    EXPECT_EQ(partial["velocity"], "4 of 5 runs (the others kept none)");
    EXPECT_TRUE(std::isfinite(partial["u_error_mean"].get<double>()));
    EXPECT_DOUBLE_EQ(partial["alpha_error_mean"].get<double>(), j["alpha_error_mean"].get<double>());

    // A campaign without snapshots is refused, naming what it needs.
    r = runMixload({"campaign", "create", "bare", "--ranges", (dir / "reg.toml").string(), "--n", "3", "--mesh", "6", "--dir",
                    dir.string()});
    ASSERT_EQ(r.rc, 0) << r.err;
    r = runMixload({"rom", "regression", "--campaign", "bare", "--dir", dir.string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("snapshots"), std::string::npos) << r.err;
    r = runMixload({"campaign", "keep-fields", "bare", "--dir", dir.string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("snapshots"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "bare" / "fields.h5"));
}

TEST(RomRegression, MixerCampaignReadsItsLoadingFromTheField) {
    // Six tiny mixer runs (gcm250, 1 cm, 0.05 s) over the bulk density: the loading that the stored
    // field gives (rho sum alpha V) is the run's own, so the POD regression's M is comparable. With
    // five training runs per left-out one, M is compared with the loading surrogate itself, and the
    // POD regression sees the runs in that surrogate's coordinates.
    const fs::path dir = scratchDir("rom-regression-mixer");
    snapshotCampaign(dir, "m", "scene = \"mixer\"\n[rho]\nmin = 300\nmax = 450\nunit = \"kg/m3\"\n",
                     {"--n", "6", "--scene", kGcm250At1cm, "--cell-size", "0.01", "--end-time", "0.05"});
    const auto r = runMixload({"rom", "regression", "--campaign", "m", "--dir", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["scene"], "mixer3d");
    EXPECT_EQ(j["inputs"], nlohmann::json::array({"rho"}));
    EXPECT_NE(j["rows"][0]["kriging_model"].get<std::string>().find("loading surrogate"), std::string::npos) << j["rows"][0];
    const auto& s = j["summary"]["loading_kg"];
    std::cout << "mixer: M from the stored field " << s["stored_field_mean_abs_error"] << ", POD regression "
              << s["pod_regression_mean_abs_error"] << ", kriging " << s["kriging_mean_abs_error"] << '\n';
    // The loading is a window mean, the field one instant: they differ by the bed's fluctuation.
    EXPECT_LT(s["stored_field_mean_abs_error"].get<double>(), 0.02);
    EXPECT_TRUE(std::isfinite(s["pod_regression_mean_abs_error"].get<double>()));
    ASSERT_FALSE(j["u_error_mean"].is_null());
    EXPECT_TRUE(std::isfinite(j["u_error_mean"].get<double>()));
    // The reduced steady model (steady powder transport on the regressed velocity) reports beside
    // them: the kept fields carry the frozen rotor's zone it needs.
    EXPECT_FALSE(store::SnapshotFile(dir / "m" / "fields.h5").mrfZones().empty());
    // Each run's window-mean field is the plain mean of its stored times in the final window
    // (result.json), counted here from the snapshot file itself; the final field's distance from
    // it is the row's alpha_fluctuation.
    int withMean = 0;
    for (const auto& f : store::campaignFinalFields(dir / "m" / "ledger.sqlite", "m").runs) {
        const store::SnapshotFile snaps(fs::path(f.run.runDir) / "snapshots.h5");
        const double window = nlohmann::json::parse(std::ifstream(fs::path(f.run.runDir) / "result.json"))["window"].get<double>();
        Eigen::VectorXd sum = Eigen::VectorXd::Zero(f.alpha.size());
        int n = 0;
        for (size_t i = 0; i < snaps.times().size(); ++i)
            if (snaps.times()[i] >= snaps.times().back() - window) sum += snaps.column("alpha", i), ++n;
        EXPECT_EQ(f.windowTimes, n >= 3 ? n : 0);
        if (n < 3) continue;
        ++withMean;
        EXPECT_LT((f.alphaWindowMean - sum / n).norm(), 1e-12 * sum.norm());
    }
    // (0.05 s runs store one time: their mean is empty, as it must be; the campaigns of docs/reduced-models.md have it.)
    EXPECT_EQ(j["window_mean_runs"], withMean);
    ASSERT_TRUE(s.contains("steady_model_mean_abs_error")) << s.dump();
    EXPECT_TRUE(std::isfinite(s["steady_model_mean_abs_error"].get<double>()));
    EXPECT_TRUE(std::isfinite(j["rows"][0]["loading_kg"]["steady_model_on_run_u"].get<double>()));
    std::cout << "mixer: steady model " << s["steady_model_mean_abs_error"] << " (on the runs' own U "
              << s["steady_model_on_run_u_mean_abs_error"] << ")\n";

    // The field's logarithm regressed instead (--field log): same runs, a field back in [0, 1].
    const auto lg = runMixload({"rom", "regression", "--campaign", "m", "--dir", dir.string(), "--field", "log", "--json"});
    ASSERT_EQ(lg.rc, 0) << lg.err;
    const auto lj = nlohmann::json::parse(lg.out);
    EXPECT_EQ(lj["regressed_field"], "ln(alpha + 0.001000)");
    EXPECT_EQ(lj["rows"][0]["regressed_field"], "ln(alpha + 0.001000)");
    EXPECT_TRUE(std::isfinite(lj["summary"]["loading_kg"]["pod_regression_mean_abs_error"].get<double>()));
    std::cout << "mixer: POD regression of ln(alpha + 0.001) "
              << lj["summary"]["loading_kg"]["pod_regression_mean_abs_error"] << '\n';
    const auto floor0 = runMixload({"rom", "regression", "--campaign", "m", "--dir", dir.string(), "--field", "log",
                                    "--log-floor", "0"});
    EXPECT_EQ(floor0.rc, 2);
    EXPECT_NE(floor0.err.find("log-floor"), std::string::npos) << floor0.err;

    // The regression's field at a new point starts a full run there (a warm start without a run):
    // the run begins with the field's loading; a field of another mesh is refused before any run.
    const auto at = runMixload({"rom", "regression", "--campaign", "m", "--dir", dir.string(), "--at", "rho=400",
                                "--fields", (dir / "at400.h5").string(), "--json"});
    ASSERT_EQ(at.rc, 0) << at.err;
    const auto atJson = nlohmann::json::parse(at.out);
    const double predicted = atJson["loading_kg"].get<double>();
    EXPECT_GT(atJson["kriging"]["loading_kg"].get<double>(), 0.0);  // the surrogate's M beside it
    const auto warm = runMixload({"mixer", "--scene", kGcm250At1cm, "--cell-size", "0.01", "--rho", "400", "--end-time",
                                  "0.02", "--warm-from", (dir / "at400.h5").string(), "--out",
                                  (dir / "warm400").string(), "--json"});
    ASSERT_EQ(warm.rc, 0) << warm.err;
    const auto w = nlohmann::json::parse(warm.out);
    EXPECT_EQ(w["start"]["warm_from"], fs::absolute(dir / "at400.h5").string());
    EXPECT_NEAR(w["start"]["field_loading_kg"].get<double>(), predicted, 1e-6 * predicted);
    EXPECT_NEAR(w["initial_loading_kg"].get<double>(), predicted, 1e-3 * predicted);  // one step of flow
    const auto other = runMixload({"mixer", "--scene", kGcm250At2cm, "--cell-size", "0.02", "--end-time", "0.02",
                                   "--warm-from", (dir / "at400.h5").string(), "--out", (dir / "other").string()});
    EXPECT_EQ(other.rc, 2) << other.err;
    EXPECT_NE(other.err.find("a field file of this run's mesh"), std::string::npos) << other.err;

    // A kept window mean of NaN (found in v2c-holdout's fields.h5 beside records that claimed a
    // mean) is no mean: the readers take the run directory's, and keep-fields writes it back. Run 0
    // is given four stored times in its final window, the last one its own final field.
    const auto runs = store::campaignFinalFields(dir / "m" / "ledger.sqlite", "m").runs;
    const fs::path run0 = runs.front().run.runDir;
    {
        const store::SnapshotFile src(run0 / "snapshots.h5");
        const double t = src.times().back();
        const Eigen::VectorXd a = src.column("alpha", src.times().size() - 1), u = src.column("U", src.times().size() - 1);
        Eigen::MatrixXd alpha(a.size(), 4), U(u.size(), 4);
        const double scale[4] = {0.9, 1.1, 0.95, 1.0};
        for (int k = 0; k < 4; ++k) alpha.col(k) = scale[k] * a, U.col(k) = u;
        writeDerivedSnapshots(src, {t - 0.03, t - 0.02, t - 0.01, t}, {{"alpha", alpha}, {"U", U}}, {{"kind", "four window times"}},
                              dir / "four.h5");
    }
    fs::rename(dir / "four.h5", run0 / "snapshots.h5");
    auto result = nlohmann::json::parse(std::ifstream(run0 / "result.json"));
    result["window"] = 0.035;
    std::ofstream(run0 / "result.json") << result.dump();
    const auto keep = [&] { return nlohmann::json::parse(runMixload({"campaign", "keep-fields", "m", "--dir", dir.string(), "--json"}).out); };
    const fs::path kept = dir / "m" / "fields.h5";
    fs::remove(kept);  // kept before run 0 had a window (a finished run's snapshots never change)
    EXPECT_EQ(keep()["added"], runs.size());
    Eigen::VectorXd expected;
    {
        const store::SnapshotFile k(kept);
        expected = k.column("alpha_window_mean", 0);
        ASSERT_TRUE(expected.allFinite());
        Eigen::MatrixXd alpha(expected.size(), static_cast<Eigen::Index>(runs.size())), U(3 * expected.size(), alpha.cols()),
            mean(expected.size(), alpha.cols());
        std::vector<double> indices;
        for (Eigen::Index i = 0; i < alpha.cols(); ++i) {
            alpha.col(i) = k.column("alpha", static_cast<size_t>(i)), U.col(i) = k.column("U", static_cast<size_t>(i));
            mean.col(i) = Eigen::VectorXd::Constant(expected.size(), std::nan(""));
            indices.push_back(runs[static_cast<size_t>(i)].run.index);
        }
        writeDerivedSnapshots(k, indices, {{"alpha", alpha}, {"U", U}, {"alpha_window_mean", mean}},
                              {{"kind", "campaign final fields"}, {"campaign", "m"}, {"kept_runs", k.provenance()["kept_runs"]}}, dir / "nan.h5");
    }
    fs::rename(dir / "nan.h5", kept);
    const auto again = store::campaignFinalFields(dir / "m" / "ledger.sqlite", "m").runs;
    EXPECT_EQ(again.front().windowTimes, 4);
    ASSERT_EQ(again.front().alphaWindowMean.size(), expected.size());
    EXPECT_LT((again.front().alphaWindowMean - expected).norm(), 1e-12 * expected.norm());
    EXPECT_EQ(keep()["window_mean_added"], 1);
    EXPECT_TRUE(store::SnapshotFile(kept).column("alpha_window_mean", 0).allFinite());
    EXPECT_EQ(keep()["window_mean_added"], 0);  // kept whole now: nothing to rewrite
}
