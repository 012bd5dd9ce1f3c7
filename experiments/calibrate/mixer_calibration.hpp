// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload calibrate mixer`: fits scene-file keys (geometry, the viscosity cap's H, ...) to
// measured loadings at one or more operating points. Every evaluation is a full run recorded in a
// SQLite ledger (<dir>/<name>/ledger.sqlite, the campaign ledger), so an interrupted calibration
// resumes: the fit is deterministic and replays its path from the ledger, runs no finished run
// again, and continues an unfinished one from its last written time.
#pragma once
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "calibrate/calibrator.hpp"
#include "scene/mixer_scene.hpp"

namespace mixload::experiments {

struct LoadingTarget {
    double rpm = 39, feedKgH = 5;
    double loadingKg = 0.311;
    double tol = 0.12;  // relative half-width of the acceptance band
};

struct MixerCalibration {
    std::string name;
    std::filesystem::path dir = "calibrations";
    std::vector<CalibrationBound> params;  // keys of the scene file, e.g. weir.chord_angle_deg
    std::vector<LoadingTarget> targets;
    // The scene of one evaluation: the base scene with these keys set, validated (throws
    // InputError otherwise). The targets then set rpm and feed.
    std::function<scene::MixerScene(const scene::SceneKeys&)> sceneFor;
    CalibrationOptions fit;
    bool allowUnsteady = false;  // count a run that hit its end time without a steady verdict
    // From the third evaluation on, start each run from a deposit the size of the loading the
    // evaluations so far predict there (depositFor), not the scene's: a deep bed that starts far
    // from its loading spends most of its run filling or draining.
    bool sizeDeposit = false;
    int np = 1;
    double maxHours = 0;         // 0: no limit; else stop (resumably) after this long
    bool progress = false;
};

// Everything that can be refused before a run: names, bounds (both ends and the start must give a
// valid scene), targets. Throws InputError.
void validateCalibration(const MixerCalibration& c);

// Runs (or resumes) the calibration; writes <dir>/<name>/report/ (calibration.csv, .md, .png,
// .json) after every evaluation and returns the report's JSON. status: within-band |
// outside-band | stopped-at-max-hours.
nlohmann::json runMixerCalibration(const MixerCalibration& c);

// The deposit for an evaluation at x [kg]: the loading interpolated (or extrapolated, from the two
// nearest) linearly in the one parameter over the evaluations so far (x, M); with several
// parameters, the loading of the nearest evaluation (in units of each range). Three significant
// digits. Fewer than two evaluations: nothing (the scene's deposit).
std::optional<double> depositFor(const std::vector<std::vector<double>>& xs, const std::vector<double>& loadings,
                                 const std::vector<double>& x, const std::vector<CalibrationBound>& bounds);

// "39:5:0.311[:0.12]" (rpm:feed:loading[:tol]); the parameters parse with parseCalibrationParam.
LoadingTarget parseLoadingTarget(const std::string& text);

}  // namespace mixload::experiments
