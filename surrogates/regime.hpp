// SPDX-License-Identifier: GPL-3.0-or-later
// The calibrated mixer's three flow regimes (issue 64), by impeller speed. Below kBedMaxRpm every
// full run on gcm250-v2 holds a dense bed (0.12-0.58 kg, residence times of 13 s to 4 min); above
// kFilmMinRpm every run from a protocol start holds a film (2-25 g, 2.5-6 s at moderate feeds); in
// between the loading falls tenfold between neighbouring runs and the start can pick the state
// (v2-holdout point 1 at 200 rpm: 0.104 kg from a dense layer, 0.027-0.045 kg on coarser meshes).
// The same split carries the shipped model's measured errors per regime (`mixload check`).
#pragma once
#include <array>
#include <cmath>

#include "inputs.hpp"

namespace mixload::surrogates {

enum class Regime { Bed = 0, Transition = 1, Film = 2 };
inline constexpr double kBedMaxRpm = 140, kFilmMinRpm = 205;

inline Regime regimeOf(const Point& x) {
    return x[kRpm] < kBedMaxRpm ? Regime::Bed : x[kRpm] > kFilmMinRpm ? Regime::Film : Regime::Transition;
}
// A regime model (kind "regimes") hands over between its parts over a few rpm either side of each
// boundary, so its answer has no jump there: logistic weights of this scale [rpm].
inline constexpr double kRegimeBlendRpm = 2.5;
// Weights of the bed, transition and film parts at rpm (they sum to one).
inline std::array<double, 3> regimeWeights(double rpm) {
    const double bed = 1 / (1 + std::exp((rpm - kBedMaxRpm) / kRegimeBlendRpm));
    const double film = 1 / (1 + std::exp((kFilmMinRpm - rpm) / kRegimeBlendRpm));
    return {bed, std::max(0.0, 1 - bed - film), film};
}

inline const char* regimeName(Regime r) {
    return r == Regime::Bed ? "bed" : r == Regime::Film ? "film" : "transition";
}

}  // namespace mixload::surrogates
