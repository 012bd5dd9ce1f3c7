// SPDX-License-Identifier: GPL-3.0-or-later
// POD regression checked on a campaign: the last stored powder fraction (and velocity, when every
// run kept one) of every finished run (campaign run --snapshots) against the run's design inputs,
// left out one run at a time. For each
// run, the field is predicted from all the others (rom/regression/pod_regression) and so is the campaign's
// quantity, by kriging on the same runs (the surrogates' way): the mixer's loading M = rho sum
// alpha V, or the collapse's L*f and H*f. The table says which predicts the held-out run better,
// and how far the predicted field is from the run's.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "inputs.hpp"

namespace mixload::rom {

struct RegressionCheckOptions {
    int modes = 0;           // POD modes of the field (0: by energy)
    double energy = 0.9999;
    // The powder fraction regressed as is, or as ln(alpha + floor): the loadings span two decades
    // (a thin film to a deep bed), and a linear mix of a film and a bed is neither; in the logarithm
    // the runs differ by factors, as the loading surrogate models M. The floor keeps air cells finite.
    bool logField = false;
    double logFloor = 1e-3;
    // Mixer campaigns: a point's seven inputs as the surrogates take them, from the campaign's base
    // scene and the point's parameters. How a campaign builds a run's scene is the experiments
    // layer's to say (experiments::mixerInputs); the loading surrogate sees the runs through it.
    std::function<surrogates::Point(const nlohmann::json& base, const nlohmann::json& params)> mixerInputs;
    // The comparison surrogate's nugget floor: the training campaign's label noise (campaign noise),
    // as `surrogate fit --noise` takes it; 0 without replicates.
    double surrogateNoise = 0;
};

// Throws InputError for a campaign without at least three finished runs with snapshots, runs on
// different meshes, or inputs that do not vary.
nlohmann::json campaignRegressionCheck(const std::filesystem::path& ledger, const std::string& campaign,
                                       const RegressionCheckOptions& options);

// The regression (and kriging) fitted on every run of one campaign, checked on every finished run
// of a hold-out campaign on the same mesh (placed by design, never used to fit): per run and in the
// mean and maximum, the field's and the quantities' errors. Hold-out runs outside the training
// box are listed.
nlohmann::json campaignRegressionHoldout(const std::filesystem::path& ledger, const std::string& campaign,
                                         const std::filesystem::path& holdoutLedger, const std::string& holdout,
                                         const RegressionCheckOptions& options);

// The same check for several regressions of one pair of campaigns (say of alpha and of ln alpha),
// the fields read once: one result per options, in their order, each with the seconds its fit took
// ("fit_seconds") beside the reading's ("load_seconds"). The options must agree on mixerInputs.
std::vector<nlohmann::json> campaignRegressionHoldouts(const std::filesystem::path& ledger, const std::string& campaign,
                                                       const std::filesystem::path& holdoutLedger, const std::string& holdout,
                                                       const std::vector<RegressionCheckOptions>& variants);

// The regression fitted on every run, at a new point (a value for each varying input): the
// quantity (M, or L*f and H*f) and, when fieldsFile is given, the predicted alpha as a snapshot
// file (+ XDMF). A point outside the training box is predicted with a warning.
nlohmann::json campaignRegressionPredict(const std::filesystem::path& ledger, const std::string& campaign,
                                         const RegressionCheckOptions& options, const std::map<std::string, double>& point,
                                         const std::filesystem::path& fieldsFile);

}  // namespace mixload::rom
