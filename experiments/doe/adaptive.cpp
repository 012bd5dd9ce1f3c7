// SPDX-License-Identifier: GPL-3.0-or-later
#include "doe/adaptive.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/input_error.hpp"
#include "kriging/kriging.hpp"

namespace mixload::experiments {

namespace {

Eigen::MatrixXd matrixOf(const Design& d, int k) {
    Eigen::MatrixXd X(static_cast<Eigen::Index>(d.size()), k);
    for (size_t i = 0; i < d.size(); ++i)
        for (int j = 0; j < k; ++j) X(static_cast<Eigen::Index>(i), j) = d[i].at(static_cast<size_t>(j));
    return X;
}

}  // namespace

AdaptiveBatch mostUncertain(const Design& done, const std::vector<double>& y, const Design& pending,
                            const Design& candidates, int n, AdaptiveCriterion by, const PointCost& cost) {
    if (done.size() < 5) throw InputError("finished runs", std::to_string(done.size()), "at least 5 to fit a model that can say where it is unsure");
    if (candidates.empty()) throw InputError("candidates", "0", "at least one");
    const int k = static_cast<int>(done.front().size());
    const Eigen::MatrixXd X = matrixOf(done, k);
    const Eigen::VectorXd Y = Eigen::Map<const Eigen::VectorXd>(y.data(), static_cast<Eigen::Index>(y.size()));
    const auto model = surrogates::Kriging::fit(X, Y, {});
    AdaptiveBatch out;
    const Eigen::VectorXd loo = model.looResiduals();
    out.looMeanAbsError = loo.cwiseAbs().mean();
    std::vector<double> weight(candidates.size(), 1.0);
    if (by == AdaptiveCriterion::LooWeighted && loo.squaredNorm() > 0) {
        const double meanSq = loo.squaredNorm() / static_cast<double>(loo.size());
        const Eigen::VectorXd& ell = model.lengthScales();
        for (size_t c = 0; c < candidates.size(); ++c) {
            double nearest = INFINITY;
            for (size_t i = 0; i < done.size(); ++i) {
                double d2 = 0;
                for (int j = 0; j < k; ++j) {
                    const double t = (candidates[c][static_cast<size_t>(j)] - done[i][static_cast<size_t>(j)]) / ell(j);
                    d2 += t * t;
                }
                if (d2 < nearest) nearest = d2, weight[c] = 1.0 + loo(static_cast<Eigen::Index>(i)) * loo(static_cast<Eigen::Index>(i)) / meanSq;
            }
        }
    }

    auto ws = model.makeWorkspace();
    const auto predictMean = [&](const std::vector<double>& p) { return model.predictMean(p.data(), ws); };
    std::vector<double> costs(candidates.size(), 0.0), perCost(candidates.size(), 1.0);
    if (cost) {
        for (size_t c = 0; c < candidates.size(); ++c) {
            costs[c] = cost(candidates[c], predictMean(candidates[c]));
            if (!(costs[c] > 0)) throw InputError("cost of a candidate", std::to_string(costs[c]), "> 0");
            perCost[c] = 1.0 / costs[c];
        }
    }

    // The conditioning set grows by the pending points and then by each pick; the length scales
    // stay those fitted to the finished runs. Points are conditioned on as exact (a jitter instead
    // of the fitted nugget): with the nugget, a well-resolved model's variance has a floor that a
    // point already run or queued does not lower enough, and the batch would repeat it. A point
    // that coincides with one already in the set adds nothing and is skipped. The values attached
    // are the model's own predictions: they do not change a variance.
    Design cond;
    std::vector<double> vals;
    const auto condition = [&](const std::vector<double>& p, double v) {
        for (const auto& q : cond) {
            double d2 = 0;
            for (int j = 0; j < k; ++j) d2 += (p[static_cast<size_t>(j)] - q[static_cast<size_t>(j)]) * (p[static_cast<size_t>(j)] - q[static_cast<size_t>(j)]);
            if (d2 < 1e-18) return;
        }
        cond.push_back(p);
        vals.push_back(v);
    };
    for (size_t i = 0; i < done.size(); ++i) condition(done[i], y[i]);
    for (const auto& p : pending) condition(p, predictMean(p));
    std::vector<bool> taken(candidates.size(), false);
    for (int i = 0; i < n; ++i) {
        const Eigen::MatrixXd C = matrixOf(cond, k);
        const Eigen::VectorXd V = Eigen::Map<const Eigen::VectorXd>(vals.data(), static_cast<Eigen::Index>(vals.size()));
        const auto believer =
            surrogates::Kriging::withHyperparameters(C, V, model.kernel(), model.trend(), model.lengthScales(), 1e-8,
                                                     model.trendInputs());
        auto bws = believer.makeWorkspace();
        double best = -1, bestVar = 0, maxVar = 0;
        size_t at = 0;
        for (size_t c = 0; c < candidates.size(); ++c) {
            if (taken[c]) continue;
            double mean = 0, var = 0;
            believer.predict(candidates[c].data(), bws, mean, var);
            maxVar = std::max(maxVar, var);
            const double score = var * weight[c] * perCost[c];
            if (score > best) best = score, bestVar = var, at = c;
        }
        if (best < 0) break;  // every candidate taken
        if (i == 0) out.maxSdBefore = std::sqrt(maxVar);
        taken[at] = true;
        AdaptivePick pick{candidates[at], std::sqrt(bestVar), predictMean(candidates[at]), weight[at], costs[at]};
        condition(pick.unit, pick.mean);
        out.picks.push_back(std::move(pick));
    }
    return out;
}

}  // namespace mixload::experiments
