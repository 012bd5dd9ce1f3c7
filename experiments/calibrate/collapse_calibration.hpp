// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload calibrate collapse`: fits the mu(I) coefficients (mu_s, mu_d, I0) and, if asked, the
// viscosity cap (its H, or a fixed eta_max) so that full 2D collapse runs meet measured final
// runouts and heights over a range of aspect ratios. One evaluation runs the collapse at every
// aspect of the data (on `jobs` threads); every run is recorded in the calibration's SQLite ledger
// (calibration_runs), so an interrupted fit resumes by running the same command again.
#pragma once
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "calibrate/calibrator.hpp"
#include "calibrate/collapse_data.hpp"
#include "scene/collapse_scene.hpp"

namespace mixload::experiments {

// The parameters a collapse fit may vary: mu_s, mu_d or delta_mu (mu_d - mu_s: keeps mu_d above
// mu_s wherever the search goes), i0, cap_h_ratio (Rauter's H / Hi) or eta_max [Pa s] (one cap
// for every column).
const std::vector<std::string>& collapseFitKeys();

struct CollapseCalibration {
    std::string name;
    std::filesystem::path dir = "calibrations";
    std::vector<CalibrationBound> params;
    CollapseData data;
    // The scene of one run: the base scene with these keys set, at this aspect, validated (throws
    // InputError otherwise).
    std::function<scene::CollapseScene(const std::map<std::string, double>&, double aspect)> sceneFor;
    CalibrationOptions fit;
    // After the fit, the best coefficients at this aspect (0: none; a run of the fit when the data
    // holds it, else one more run): does a squat column keep its height (H*f = 1)?
    double checkAspect = 0.5;
    int jobs = 1;
    double maxHours = 0;
    bool progress = false;
};

void validateCollapseCalibration(const CollapseCalibration& c);

// Runs (or resumes) the fit; writes <dir>/<name>/report/ (calibration.md, .csv, .png, .json)
// after every evaluation and returns the report. status: within-uncertainty (rms of the residuals,
// in standard uncertainties, at most 1) | outside-uncertainty | stopped-at-max-hours.
nlohmann::json runCollapseCalibration(const CollapseCalibration& c);

// Residual of a model value against a measured one, in the measurement's standard uncertainty.
inline double standardResidual(double model, double measured, double sd) { return (model - measured) / sd; }

}  // namespace mixload::experiments
