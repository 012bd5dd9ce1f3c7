// SPDX-License-Identifier: GPL-3.0-or-later
// A mixer campaign's finished, steady runs as surrogate training data.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "table.hpp"

namespace mixload::experiments {

// Throws InputError if the campaign does not exist or is not a mixer campaign. provenance gets the
// campaign's name, ledger path, design, base scene and the code that created it.
surrogates::Table campaignTable(const std::string& name, const std::string& dir, nlohmann::json& provenance);

}  // namespace mixload::experiments
