// SPDX-License-Identifier: GPL-3.0-or-later
// Adaptive sampling: the next points of a campaign where a kriging model of the finished runs is
// least sure. A batch is chosen one point at a time; each chosen point (and every point already
// queued or running) is conditioned on before the next is chosen, so a batch spreads out instead
// of piling into one gap. The predictive variance does not depend on the values at those points,
// only on where they are, so nothing has to be guessed for them.
#pragma once
#include <vector>

#include <Eigen/Dense>

#include "designs.hpp"

namespace mixload::experiments {

struct AdaptivePick {
    std::vector<double> unit;  // the point, unit-cube coordinates
    double sd = 0;             // the model's predictive standard deviation there when it was chosen (every
                               // point so far taken as exact; the process variance fitted to the runs)
    double mean = 0;           // the model's prediction there
};

struct AdaptiveBatch {
    std::vector<AdaptivePick> picks;
    double looMeanAbsError = 0;  // of the model on the finished runs, in the output's units
    double maxSdBefore = 0;      // largest predictive sd over the candidates before the batch
};

// done: finished runs (unit coordinates) and their outputs; pending: points already in the queue;
// candidates: where a new point may go (e.g. a Sobol set). Throws InputError with fewer than 5
// finished runs or an empty candidate set.
AdaptiveBatch mostUncertain(const Design& done, const std::vector<double>& y, const Design& pending,
                            const Design& candidates, int n);

}  // namespace mixload::experiments
