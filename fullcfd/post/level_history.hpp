// SPDX-License-Identifier: GPL-3.0-or-later
// How a loading history reached its final level: when it last left a band about that level, how
// many residence times it has held since, and whether it had reached the level once and then left
// it again (a plateau, an overshoot or a surge: the sign of a second state the run passed through).
// The label protocol (scene/label_protocol.hpp) reads these, so a run the steady test called at one
// residence time on a metastable plateau is not taken for a label (issue 64: the reference point
// sat 700 s on a 0.39-0.40 kg plateau before it surged to 0.331 kg).
#pragma once
#include <vector>

namespace mixload::post {

struct LevelHistory {
    double finalLevel = 0;           // the mean loading over the final window [kg]
    double residenceTime = 0;        // finalLevel / feed [s]
    double settledAt = 0;            // last time the smoothed loading lay outside the band [s]
    double settledResidenceTimes = 0;  // (end - settledAt) / residenceTime
    bool levelChangeSeen = false;    // inside the band once, then outside again for a smoothing span
    double band = 0;                 // the band's half-width, a fraction of finalLevel
    double smoothing = 0;            // the span of the trailing mean the band is tested on [s]
};

// t ascending, M the loading [kg] at each t, feed [kg/s] > 0. The loading is smoothed by a trailing
// mean over `smoothing` seconds (whole revolutions: the paddles' passage moves M periodically), and
// the smoothed value is compared with the final window's mean over `finalWindow` seconds.
LevelHistory levelHistory(const std::vector<double>& t, const std::vector<double>& M, double feedKgS,
                          double finalWindow, double smoothing, double band = 0.05);

}  // namespace mixload::post
