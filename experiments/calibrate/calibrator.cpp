// SPDX-License-Identifier: GPL-3.0-or-later
#include "calibrate/calibrator.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <stdexcept>

#include <nlopt.h>

namespace mixload::experiments {

namespace {

struct Context {
    const std::vector<CalibrationBound>* bounds;
    const ResidualFn* residuals;
    const std::function<void(const CalibrationTrace&)>* onEval;
    CalibrationTrace trace;
    std::exception_ptr error;
    nlopt_opt opt = nullptr;
};

// NLopt works on [0, 1] per parameter, so that one step size and one tolerance fit every key.
double objective(unsigned n, const double* u, double*, void* data) {
    auto& c = *static_cast<Context*>(data);
    try {
        std::vector<double> x(n);
        for (unsigned i = 0; i < n; ++i) {
            const auto& b = (*c.bounds)[i];
            x[i] = b.lo + std::clamp(u[i], 0.0, 1.0) * (b.hi - b.lo);
        }
        const std::vector<double> r = (*c.residuals)(x);
        if (r.empty()) throw std::logic_error("calibrate: no residuals");
        double ss = 0;
        for (double v : r) ss += v * v;
        const double rms = std::sqrt(ss / r.size());
        auto& t = c.trace;
        t.x.push_back(x);
        t.r.push_back(r);
        t.rms.push_back(rms);
        if (rms < t.rms[t.best]) t.best = t.rms.size() - 1;
        if (*c.onEval) (*c.onEval)(t);
        return rms * rms;
    } catch (...) {
        c.error = std::current_exception();
        nlopt_force_stop(c.opt);
        return HUGE_VAL;
    }
}

std::string stopName(nlopt_result r) {
    switch (r) {
        case NLOPT_STOPVAL_REACHED: return "within-stop-rms";
        case NLOPT_XTOL_REACHED: return "xtol";
        case NLOPT_FTOL_REACHED: return "ftol";
        case NLOPT_MAXEVAL_REACHED: return "max-evals";
        case NLOPT_SUCCESS: return "converged";
        default: return "nlopt-" + std::to_string(static_cast<int>(r));
    }
}

}  // namespace

CalibrationTrace calibrate(const std::vector<CalibrationBound>& bounds, const ResidualFn& residuals,
                           const CalibrationOptions& opt,
                           const std::function<void(const CalibrationTrace&)>& onEval) {
    const unsigned n = static_cast<unsigned>(bounds.size());
    if (n == 0) throw std::invalid_argument("calibrate: no parameters");
    Context c{&bounds, &residuals, &onEval, {}, nullptr, nullptr};
    // BOBYQA: bounded, derivative-free, with a quadratic model that suits a sum of squares. On the
    // analytic responses of the unit tests it needed 5-10 evaluations in one dimension and 9 in
    // two, against 4-9 and 21 for COBYLA and 6-9 and 42 for Subplex.
    std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> o(nlopt_create(NLOPT_LN_BOBYQA, n), &nlopt_destroy);
    if (!o) throw std::runtime_error("calibrate: nlopt_create failed");
    c.opt = o.get();
    std::vector<double> lb(n, 0.0), ub(n, 1.0), step(n, 0.25), u(n);
    for (unsigned i = 0; i < n; ++i) {
        const auto& b = bounds[i];
        if (!(b.hi > b.lo)) throw std::invalid_argument("calibrate: empty range for " + b.key);
        u[i] = std::clamp((b.start - b.lo) / (b.hi - b.lo), 0.0, 1.0);
    }
    nlopt_set_lower_bounds(o.get(), lb.data());
    nlopt_set_upper_bounds(o.get(), ub.data());
    nlopt_set_min_objective(o.get(), &objective, &c);
    nlopt_set_initial_step(o.get(), step.data());
    nlopt_set_stopval(o.get(), opt.stopRms * opt.stopRms);
    nlopt_set_xtol_abs1(o.get(), opt.xtolShare);
    nlopt_set_maxeval(o.get(), opt.maxEvals);
    double f = 0;
    const nlopt_result res = nlopt_optimize(o.get(), u.data(), &f);
    if (c.error) std::rethrow_exception(c.error);
    c.trace.stop = stopName(res);
    return c.trace;
}

}  // namespace mixload::experiments
