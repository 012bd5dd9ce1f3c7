// SPDX-License-Identifier: GPL-3.0-or-later
// Adaptive sampling: the next points of a campaign where a kriging model of the finished runs is
// least sure. A batch is chosen one point at a time; each chosen point (and every point already
// queued or running) is conditioned on before the next is chosen, so a batch spreads out instead
// of piling into one gap. The predictive variance does not depend on the values at those points,
// only on where they are, so nothing has to be guessed for them.
//
// LooWeighted multiplies that variance by 1 + e_j^2 / mean(e^2), where e_j is the leave-one-out
// residual of the finished run nearest to the candidate (in the model's length scales): a model
// that misses its own runs somewhere (a regime boundary, a step) is less sure near them than its
// variance says, which depends only on where the runs are. Picks still lower the variance around
// them, so a batch spreads out as before.
//
// With a cost (what a point would take to run, from where it is and what the model predicts
// there), the criterion is divided by it: the most uncertainty removed per core-hour, for a
// machine where the runs are the scarce resource and some corners cost forty times others.
#pragma once
#include <functional>
#include <vector>

#include <Eigen/Dense>

#include "designs.hpp"

namespace mixload::experiments {

enum class AdaptiveCriterion { Variance, LooWeighted };

struct AdaptivePick {
    std::vector<double> unit;  // the point, unit-cube coordinates
    double sd = 0;             // the model's predictive standard deviation there when it was chosen (every
                               // point so far taken as exact; the process variance fitted to the runs)
    double mean = 0;           // the model's prediction there
    double weight = 1;         // the criterion's factor on the variance there (1 for Variance)
    double cost = 0;           // the cost there (0 when the batch was chosen without one)
};

// A point's cost from its unit coordinates and the model's prediction there; must be > 0.
using PointCost = std::function<double(const std::vector<double>& unit, double predicted)>;

struct AdaptiveBatch {
    std::vector<AdaptivePick> picks;
    double looMeanAbsError = 0;  // of the model on the finished runs, in the output's units
    double maxSdBefore = 0;      // largest predictive sd over the candidates before the batch
};

// done: finished runs (unit coordinates) and their outputs; pending: points already in the queue;
// candidates: where a new point may go (e.g. a Sobol set). Throws InputError with fewer than 5
// finished runs or an empty candidate set.
AdaptiveBatch mostUncertain(const Design& done, const std::vector<double>& y, const Design& pending,
                            const Design& candidates, int n, AdaptiveCriterion by = AdaptiveCriterion::Variance,
                            const PointCost& cost = {});

}  // namespace mixload::experiments
