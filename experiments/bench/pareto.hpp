// SPDX-License-Identifier: GPL-3.0-or-later
// Time against error for a set of methods answering the same held-out questions (issue 19): the
// Pareto front, and one table, CSV and log-log PNG, shared by the collapse's and the mixer's
// benchmarks so that both draw the front the same way.
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mixload::experiments {

struct ParetoMethod {
    std::string name;
    double seconds = 0, error = 0;  // median online time per answer; the error the front is drawn on
    std::vector<double> errors;     // the table's error columns (medians), one per ParetoPlot::errorKeys
    double offlineSeconds = 0;
    bool reference = false, front = false;
};

// Marks the methods no other beats on both time and error (ties count as not beaten).
void markParetoFront(std::vector<ParetoMethod>& methods);

struct ParetoPlot {
    std::string caption;                  // the table's first paragraph
    std::string title;                    // the PNG's title
    std::string timeLabel, errorLabel;    // the PNG's axes
    std::vector<std::string> errorHeads;  // table headers of ParetoMethod::errors
    std::vector<std::string> errorKeys;   // their CSV and JSON keys
};

// Marks the front and writes <out>/pareto.md, pareto.csv and pareto.png (the reference drawn at an
// error floor of 1e-4); returns {"pareto": [...], "pareto_table", "pareto_plot"[, "pareto_warning"]}.
nlohmann::json writePareto(const std::filesystem::path& out, const ParetoPlot& plot, std::vector<ParetoMethod>& methods);

}  // namespace mixload::experiments
