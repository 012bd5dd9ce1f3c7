// SPDX-License-Identifier: GPL-3.0-or-later
// Space-filling designs on the unit cube [0,1)^k; ParameterSpace::toPhysical maps them to inputs.
#pragma once
#include <cstdint>
#include <vector>

namespace mixload::experiments {

using Design = std::vector<std::vector<double>>;  // n points x k coordinates

// Latin hypercube: in every dimension exactly one point per stratum [i/n, (i+1)/n). Of
// `candidates` random hypercubes drawn from the seed, the one with the largest smallest pairwise
// distance (maximin). Same seed, same design.
Design latinHypercube(int n, int k, std::uint64_t seed, int candidates = 200);

// m new points for an existing design, none repeating an old one: in every dimension the new
// points take strata of the finer n+m division that no existing point occupies (so the union
// stays as close to a Latin hypercube as the old points allow), maximin over candidates.
Design augmentLatinHypercube(const Design& existing, int m, std::uint64_t seed, int candidates = 200);

// Points skip .. skip+n-1 of GSL's Sobol sequence (k <= 40). Extending a Sobol design of n points
// is sobol(m, k, n): the sequence continues, nothing repeats.
Design sobol(int n, int k, int skip = 0);

// Smallest Euclidean distance between two points of the design (0 for fewer than 2 points).
double minDistance(const Design& d);

}  // namespace mixload::experiments
