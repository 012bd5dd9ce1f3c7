// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload study formulation`: how the loading answers changes of the powder, as full runs against
// a reference, each change compared with what the paper reports for it (its two what-ifs and the
// signs of its Fig. 7), pass or fail with the measured number.
#pragma once
#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "model.hpp"
#include "scene/mixer_scene.hpp"

namespace mixload::experiments {

// A change of the formulation: factors on mu_s, mu_d, i0, d, rho (bulk density; the grain density
// follows), and what the paper found for it: a relative change of M (its what-ifs) or only a sign
// (its Fig. 7 trends).
struct FormulationVariant {
    std::string name;
    std::map<std::string, double> factors;
    std::optional<double> paperChange;  // e.g. +0.25
    int paperSign = 0;                  // +1 | -1 | 0 (no expectation)
};

// Named sets: paper-whatifs (the paper's two arrows on its Fig. 8), fig7-signs (each of mu_s,
// mu_d, i0, d, rho at 0.8 and 1.2), fig7 (each at six factors 0.7-1.3), fig7-similar (fig7 without
// I0, whose panel the d runs give by similarity), all (paper-whatifs and fig7-signs).
std::vector<FormulationVariant> formulationPreset(const std::string& name);
// The same, only the variants valid at this reference; the others (mu_d x 0.7 below mu_s on
// gcm250-v2) go to `skipped` with the reason, so that a study runs the rest and its table says why.
std::vector<FormulationVariant> formulationPreset(const std::string& name, const scene::MixerScene& reference,
                                                  std::vector<std::pair<std::string, std::string>>& skipped);
// "NAME:key=factor[,key=factor...]" (keys mu_s, mu_d, i0, d, rho). InputError otherwise.
FormulationVariant parseFormulationVariant(const std::string& text);
// The reference scene with the variant's factors applied, validated (InputError: mu_d <= mu_s...).
scene::MixerScene applyVariant(scene::MixerScene s, const FormulationVariant& v);

struct FormulationStudy {
    scene::MixerScene reference;
    std::vector<FormulationVariant> variants;
    // A preset's variants left out as invalid at this reference: name and the reason.
    std::vector<std::pair<std::string, std::string>> skipped;
    std::filesystem::path out;
    std::filesystem::path runs;  // empty: <out>/runs
    int jobs = 1, np = 1;
    bool progress = false;
    // Every run (reference and variants) starts from this run directory's latest fields instead of
    // the scene's deposit: a converged reference bed, so that each run only relaxes to its change.
    std::filesystem::path warmFrom;
    // Runs still going then stop and keep what they ran; the same study resumes them.
    std::optional<std::chrono::steady_clock::time_point> deadline;
    // A surrogate whose Fig. 7 curves are drawn beside the full runs' (fig7ModelCurves).
    std::optional<surrogates::Surrogate> model;
    std::string modelPath;
};

// The paper's Fig. 7 from a study's rows (variant rows with factors, sign_paper and, when steady,
// change_model): per parameter changed alone, M / M_reference against the parameter / its
// reference value with the reference as (1, 1), a least-squares line, its slope (the elasticity of
// M) and whether its sign is the paper's. Parameters without a steady variant are left out, except
// I0, which without runs of its own mirrors the d runs (I0 x f = d x 1/f; "from" says so).
nlohmann::json fig7Fit(const nlohmann::json& rows);

// The surrogate's Fig. 7: per parameter, the model's M with that parameter alone scaled by 0.70 to
// 1.30 at the reference scene, over the model's own M at the reference (so that its shape, not its
// bias, is compared with the full runs'), the least-squares slope of that curve, the model's
// M/M0 at x0.8 and x1.2, and the factors where the point leaves the model's training box. Factors
// the scene refuses (mu_d <= mu_s) are left out.
nlohmann::json fig7ModelCurves(const surrogates::Surrogate& model, const scene::MixerScene& reference);

// Runs the reference and every variant (resumable, shared run store) and writes <out>/table.md,
// table.csv, formulation.png (model against paper, relative change of M), study.json and, from the
// one-parameter variants that are steady and from the surrogate if given, fig7.md, .csv and .png.
nlohmann::json runFormulationStudy(const FormulationStudy& study);

}  // namespace mixload::experiments
