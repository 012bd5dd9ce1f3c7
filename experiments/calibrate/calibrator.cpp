// SPDX-License-Identifier: GPL-3.0-or-later
#include "calibrate/calibrator.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <nlopt.h>

#include "common/input_error.hpp"

namespace mixload::experiments {

namespace {

struct Context {
    const std::vector<CalibrationBound>* bounds;
    const ResidualFn* residuals;
    const std::function<void(const CalibrationTrace&)>* onEval;
    CalibrationTrace trace;
    std::exception_ptr error;
    nlopt_opt opt = nullptr;

    // The residuals at x, evaluated once: a point the search comes back to costs nothing and
    // enters the trace once.
    const std::vector<double>& at(const std::vector<double>& x) {
        for (size_t i = 0; i < trace.x.size(); ++i)
            if (trace.x[i] == x) return trace.r[i];
        const std::vector<double> r = (*residuals)(x);
        if (r.empty()) throw std::logic_error("calibrate: no residuals");
        double ss = 0;
        for (double v : r) ss += v * v;
        trace.x.push_back(x);
        trace.r.push_back(r);
        trace.rms.push_back(std::sqrt(ss / r.size()));
        if (trace.rms.back() < trace.rms[trace.best]) trace.best = trace.rms.size() - 1;
        if (*onEval) (*onEval)(trace);
        return trace.r.back();
    }
};

// NLopt works on [0, 1] per parameter, so that one step size and one tolerance fit every key.
double physical(const CalibrationBound& b, double u) {
    u = std::clamp(u, 0.0, 1.0);
    return b.log ? b.lo * std::pow(b.hi / b.lo, u) : b.lo + u * (b.hi - b.lo);
}
double unit(const CalibrationBound& b, double x) {
    return std::clamp(b.log ? std::log(x / b.lo) / std::log(b.hi / b.lo) : (x - b.lo) / (b.hi - b.lo), 0.0, 1.0);
}

double objective(unsigned n, const double* u, double*, void* data) {
    auto& c = *static_cast<Context*>(data);
    try {
        std::vector<double> x(n);
        for (unsigned i = 0; i < n; ++i) x[i] = physical((*c.bounds)[i], u[i]);
        const std::vector<double>& r = c.at(x);
        double ss = 0;
        for (double v : r) ss += v * v;
        return ss / r.size();
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

// One parameter, one target: a root of the residual, found by bracketing and the Illinois
// variant of regula falsi. For a handful of full runs this beats a general minimiser: BOBYQA
// spends its first three evaluations on x0 and x0 +- a quarter of the range whatever they show.
// (Written out rather than GSL's Brent solver so that an exception from a run passes through and
// every evaluation is counted.)
CalibrationTrace findRoot(Context& c, const CalibrationOptions& opt) {
    // In the unit coordinate of the parameter (linear or log), so both scales share the steps.
    const auto& b = (*c.bounds)[0];
    const double step = 0.25, xtol = opt.xtolShare;
    auto f = [&](double u) { return c.at({physical(b, u)})[0]; };
    auto done = [&](const std::string& why) {
        c.trace.stop = why;
        return c.trace;
    };
    const auto within = [&](double r) { return std::abs(r) <= opt.stopRms; };
    auto budget = [&] { return static_cast<int>(c.trace.x.size()) < opt.maxEvals; };
    double x0 = unit(b, b.start), r0 = f(x0);
    if (within(r0)) return done("within-stop-rms");
    if (!budget()) return done("max-evals");
    double x1 = x0 + step <= 1 ? x0 + step : x0 - step, r1 = f(x1);
    // Bracket: follow the secant (at least one step, at most to a bound) until the sign changes.
    while (r0 * r1 > 0) {
        if (within(r1)) return done("within-stop-rms");
        if (!budget()) return done("max-evals");
        double next = r1 != r0 ? x1 - r1 * (x1 - x0) / (r1 - r0) : x1 + (x1 - x0);
        const double dir = next > x1 ? 1 : -1;
        if (std::abs(next - x1) < step) next = x1 + dir * step;
        next = std::clamp(next, 0.0, 1.0);
        if (next == x1 || next == x0) return done("bound");  // the target lies beyond the range
        x0 = x1, r0 = r1;
        x1 = next, r1 = f(x1);
    }
    // Illinois: regula falsi that halves the stale end's residual, so both ends move.
    double a = x0, fa = r0, z = x1, fz = r1;
    for (;;) {
        if (within(fz)) return done("within-stop-rms");
        if (std::abs(z - a) < xtol) return done("xtol");
        if (!budget()) return done("max-evals");
        const double x = z - fz * (z - a) / (fz - fa), fx = f(x);
        if (fx * fz < 0) a = z, fa = fz;
        else fa *= 0.5;
        z = x, fz = fx;
    }
}

}  // namespace

std::vector<std::string> splitColons(const std::string& s) {
    std::vector<std::string> out;
    std::stringstream ss(s);
    for (std::string part; std::getline(ss, part, ':');) out.push_back(part);
    return out;
}

double parseFieldNumber(const std::string& field, const std::string& text, const std::string& whole) {
    const auto v = parseNumber(text);
    if (!v || !std::isfinite(*v)) throw InputError(field, whole, "numbers separated by ':'");
    return *v;
}

CalibrationBound parseCalibrationParam(const std::string& text, bool dotted) {
    const auto eq = text.find('=');
    const std::string key = text.substr(0, eq);
    const std::string form = dotted ? "TABLE.KEY=LO:HI[:START][:log], e.g. weir.chord_angle_deg=20:88"
                                    : "KEY=LO:HI[:START][:log], e.g. mu_s=0.3:0.6";
    if (eq == std::string::npos || key.empty() || (dotted && key.find('.') == std::string::npos))
        throw InputError("param", text, form);
    auto parts = splitColons(text.substr(eq + 1));
    const bool log = !parts.empty() && parts.back() == "log";
    if (log) parts.pop_back();
    if (parts.size() < 2 || parts.size() > 3) throw InputError("param " + key, text.substr(eq + 1), "LO:HI[:START][:log]");
    CalibrationBound b{key, parseFieldNumber("param " + key, parts[0], text),
                       parseFieldNumber("param " + key, parts[1], text), 0, log};
    if (!(b.hi > b.lo)) throw InputError("param " + key, text.substr(eq + 1), "LO < HI");
    if (log && !(b.lo > 0)) throw InputError("param " + key, text.substr(eq + 1), "LO > 0 on a log scale");
    b.start = parts.size() == 3 ? parseFieldNumber("param " + key, parts[2], text)
              : log            ? std::sqrt(b.lo * b.hi)
                               : 0.5 * (b.lo + b.hi);
    requireRange("param " + key + " start", b.start, b.lo, b.hi);
    return b;
}

CalibrationTrace calibrate(const std::vector<CalibrationBound>& bounds, const ResidualFn& residuals,
                           const CalibrationOptions& opt,
                           const std::function<void(const CalibrationTrace&)>& onEval) {
    const unsigned n = static_cast<unsigned>(bounds.size());
    if (n == 0) throw std::invalid_argument("calibrate: no parameters");
    for (const auto& b : bounds) {
        if (!(b.hi > b.lo)) throw std::invalid_argument("calibrate: empty range for " + b.key);
        if (b.log && !(b.lo > 0)) throw std::invalid_argument("calibrate: log range of " + b.key + " not positive");
    }
    Context c{&bounds, &residuals, &onEval, {}, nullptr, nullptr};
    if (n == 1 && opt.residuals == 1) return findRoot(c, opt);
    // BOBYQA: bounded, derivative-free, with a quadratic model that suits a sum of squares. On the
    // analytic responses of the unit tests it needed 5-10 evaluations in one dimension and 9 in
    // two, against 4-9 and 21 for COBYLA and 6-9 and 42 for Subplex.
    std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> o(nlopt_create(NLOPT_LN_BOBYQA, n), &nlopt_destroy);
    if (!o) throw std::runtime_error("calibrate: nlopt_create failed");
    c.opt = o.get();
    std::vector<double> lb(n, 0.0), ub(n, 1.0), step(n, 0.25), u(n);
    for (unsigned i = 0; i < n; ++i) u[i] = unit(bounds[i], bounds[i].start);
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
