// SPDX-License-Identifier: GPL-3.0-or-later
// A mixer campaign's finished, steady runs as surrogate training data.
#pragma once
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "inputs.hpp"
#include "scene/mixer_scene.hpp"
#include "table.hpp"

namespace mixload::experiments {

// Throws InputError if the campaign does not exist or is not a mixer campaign. provenance gets the
// campaign's name, ledger path, design, base scene and the code that created it.
// A mixer point's seven inputs as the surrogates take them, read off its scene (the campaign's base
// with the point's parameters applied), so that the surrogates' table and the POD regression see a
// run alike.
surrogates::Point mixerInputs(const nlohmann::json& base, const nlohmann::json& params);
// The same seven inputs read off a scene.
surrogates::Point sceneInputs(const scene::MixerScene& s);

// A mixer campaign's base scene (no point's parameters applied): its barrel's open volume bounds
// every loading (a full barrel of the powder), its cell size names the mesh a model learnt. Nothing
// for a base that is not a mixer's or that no longer makes a scene.
std::optional<scene::MixerScene> campaignBaseScene(const nlohmann::json& base);

surrogates::Table campaignTable(const std::string& name, const std::string& dir, nlohmann::json& provenance);

}  // namespace mixload::experiments
