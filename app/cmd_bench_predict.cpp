// SPDX-License-Identifier: GPL-3.0-or-later
// mixload bench predict: time per prediction in-process (>= 1e6 calls) for the response surface
// and kriging, beside their accuracy, and the wall time of whole `mixload predict` processes.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <random>

#include "app/commands.hpp"
#include "app/point_options.hpp"
#include "common/input_error.hpp"
#include "common/process.hpp"
#include "model.hpp"

namespace mixload::app {

namespace {

struct BenchPredict {
    std::string rsm, kriging;
    long calls = 1000000;
    int processes = 20;
    bool json = false;
};

std::string rsmDefault() { return std::string(MIXLOAD_DATA_DIR) + "/models/mixer-loading-rsm.json"; }

// Points spread over the model's training box, drawn once (not timed).
std::vector<surrogates::Point> pointsIn(const surrogates::Surrogate& m, size_t n) {
    std::mt19937 g(1);
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<surrogates::Point> pts(n);
    for (auto& p : pts)
        for (size_t k = 0; k < surrogates::kInputs; ++k) p[k] = m.boxMin()[k] + u(g) * (m.boxMax()[k] - m.boxMin()[k]);
    return pts;
}

double nsPerPrediction(const surrogates::Surrogate& m, long calls) {
    const auto pts = pointsIn(m, 1024);
    auto ws = m.makeWorkspace();
    double sink = 0;
    const auto t0 = std::chrono::steady_clock::now();
    for (long i = 0; i < calls; ++i) sink += m.predict(pts[static_cast<size_t>(i) & 1023], ws).m;
    const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
    if (!std::isfinite(sink)) throw std::runtime_error("bench: a prediction was not finite");
    return ns / static_cast<double>(calls);
}

// Median wall time of whole `mixload predict --json` processes at the paper's reference point.
double processMs(const std::string& model, int n) {
    const std::string self = std::filesystem::read_symlink("/proc/self/exe");
    std::vector<double> ms;
    for (int i = 0; i < n; ++i) {
        ProcessSpec spec;
        spec.argv = {self, "predict", "--model", model, "--mu-s", "0.31", "--mu-d", "0.44", "--i0", "0.28", "--d",
                     "240e-6", "--rho", "329.84", "--feed-kg-h", "5", "--rpm", "39", "--json"};
        spec.onLine = [](const std::string&) {};
        const auto t0 = std::chrono::steady_clock::now();
        if (runProcess(spec) != 0) throw std::runtime_error("bench: `mixload predict` failed");
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::sort(ms.begin(), ms.end());
    return ms[ms.size() / 2];
}

int run(const BenchPredict& o) {
    requireRange("calls", static_cast<double>(o.calls), 1e6, 1e10);
    requireRange("processes", o.processes, 1, 1000);
    const auto rsm = surrogates::Surrogate::load(o.rsm), kr = surrogates::Surrogate::load(o.kriging);
    nlohmann::json out{{"rsm_ns_per_prediction", nsPerPrediction(rsm, o.calls)},
                       {"kriging_ns_per_prediction", nsPerPrediction(kr, o.calls)},
                       {"calls", o.calls},
                       {"process_ms", processMs(o.kriging, o.processes)},
                       {"processes", o.processes},
                       {"rsm_model", o.rsm},
                       {"kriging_model", o.kriging},
                       {"rsm_loo_mean_rel_error", rsm.validation()["mean_rel_error"]},
                       {"kriging_loo_mean_rel_error", kr.validation()["mean_rel_error"]},
                       {"rsm_training_runs", rsm.trainingIds().size()},
                       {"kriging_training_runs", kr.trainingIds().size()}};
    const auto lastCheck = [](const surrogates::Surrogate& m) {
        const auto& c = m.checkHistory();
        return c.empty() ? nlohmann::json() : c.back()["mean_rel_error"];
    };
    out["rsm_holdout_mean_rel_error"] = lastCheck(rsm);
    out["kriging_holdout_mean_rel_error"] = lastCheck(kr);
    if (o.json) {
        std::cout << out.dump(2) << '\n';
        return 0;
    }
    const auto pct = [](const nlohmann::json& v) {
        std::ostringstream os;
        if (v.is_null()) os << "n/a";
        else os << std::fixed << std::setprecision(2) << 100 * v.get<double>() << "%";
        return os.str();
    };
    std::cout << std::fixed << std::setprecision(1) << "prediction time (" << o.calls << " calls in-process) and error:\n"
              << "  rsm      " << std::setw(8) << out["rsm_ns_per_prediction"].get<double>() << " ns   LOO mean "
              << pct(out["rsm_loo_mean_rel_error"]) << ", last hold-out check " << pct(out["rsm_holdout_mean_rel_error"])
              << "\n  kriging  " << std::setw(8) << out["kriging_ns_per_prediction"].get<double>() << " ns   LOO mean "
              << pct(out["kriging_loo_mean_rel_error"]) << ", last hold-out check "
              << pct(out["kriging_holdout_mean_rel_error"]) << "\n  whole `mixload predict` process: "
              << out["process_ms"].get<double>() << " ms (median of " << o.processes << ")\n";
    return 0;
}

}  // namespace

void addBenchPredict(CLI::App* bench, Action& action) {
    auto* p = bench->add_subcommand("predict", "Surrogate prediction time (in-process, >= 1e6 calls) and process time, beside accuracy");
    auto o = std::make_shared<BenchPredict>();
    o->rsm = rsmDefault();
    o->kriging = defaultModelPath();
    p->add_option("--rsm", o->rsm, "Response-surface model")->capture_default_str();
    p->add_option("--kriging", o->kriging, "Kriging model")->capture_default_str();
    p->add_option("--calls", o->calls, "Predictions per model (>= 1e6)")->capture_default_str();
    p->add_option("--processes", o->processes, "`mixload predict` processes to time (median)")->capture_default_str();
    p->add_flag("--json", o->json, "Print JSON: rsm_ns_per_prediction, kriging_ns_per_prediction, process_ms, ...");
    p->callback([&action, o] { action = [o] { return run(*o); }; });
}

}  // namespace mixload::app
