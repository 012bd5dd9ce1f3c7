// SPDX-License-Identifier: GPL-3.0-or-later
// The picture of a check: does the model's answer sit on the full runs' loadings, and do its
// intervals hold them?
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

namespace mixload::surrogates {

// Writes dir/parity.png (with parity.dat and parity.gp) from checkModel's result: every checked
// run's full-run M against the model's answer and its 95% interval, log-log, hold-out runs inside
// and outside their intervals apart from the training runs' leave-one-out answers, with the line
// of equality and the ±10% band of the accuracy target. Returns the PNG, or nothing and the reason
// in `warning` (a plot never fails a check).
std::optional<std::filesystem::path> plotCheck(const nlohmann::json& check, const std::string& title,
                                               const std::filesystem::path& dir, std::string& warning);

}  // namespace mixload::surrogates
