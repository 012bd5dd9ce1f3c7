// SPDX-License-Identifier: GPL-3.0-or-later
// `mixload stress`: parses the sweep's options and prints its counts; the cases and their judging
// are experiments/stress.
#include <iostream>

#include "app/commands.hpp"
#include "stress/stress.hpp"

namespace mixload::app {

void addStress(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand(
        "stress",
        "Try to break the solver and the tools (extreme rheology, operation and numerics, killed runs, full "
        "disks, corrupted files, two drivers, surrogates far outside their box); every case must end as a "
        "result whose own checks pass or a clear error. Exit 1 on any silent failure");
    auto o = std::make_shared<experiments::StressOptions>();
    auto json = std::make_shared<bool>(false);
    auto out = std::make_shared<std::string>("runs/stress");
    cmd->add_flag("--full", o->full, "Add the full tier: tiny mixer runs (minutes), beside the quick tier (CI)");
    cmd->add_option("--only", o->only, "Only these groups: rheology, numerics, operation, faults, surrogates")
        ->delimiter(',')
        ->check(CLI::IsMember({"rheology", "numerics", "operation", "faults", "surrogates"}));
    cmd->add_option("--out", *out, "Where the cases' directories and the table go")->capture_default_str();
    cmd->add_flag("--json", *json, "Print the report as JSON");
    cmd->callback([&action, o, json, out] {
        action = [o, json, out] {
            o->out = *out;
            o->exe = std::filesystem::read_symlink("/proc/self/exe");
            o->progress = !*json;
            const auto r = experiments::runStress(*o);
            if (*json) std::cout << r.dump(2) << '\n';
            else
                std::cout << "stress (" << r["tier"].get<std::string>() << " tier): " << r["cases"] << " cases, "
                          << r["results"] << " results whose checks pass, " << r["clear_errors"] << " clear errors, "
                          << r["skipped"] << " skipped, " << r["silent_failures"] << " silent failures\n  table "
                          << r["table_md"].get<std::string>() << '\n';
            for (const auto& row : r["rows"])
                if (row["class"] == "silent-failure")
                    std::cerr << "mixload: silent failure: " << row["group"].get<std::string>() << '/'
                              << row["case"].get<std::string>() << ": " << row["why"].get<std::string>() << '\n';
            return r["silent_failures"].get<int>() > 0 ? 1 : 0;
        };
    });
}

}  // namespace mixload::app
