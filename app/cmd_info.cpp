// SPDX-License-Identifier: GPL-3.0-or-later
#include <iostream>

#include <nlohmann/json.hpp>

#include "app/commands.hpp"
#include "cases/foam_numerics.hpp"
#include "mixload_version.hpp"

namespace mixload::app {

void addInfo(CLI::App& app, Action& action) {
    auto* cmd = app.add_subcommand("info", "Versions, library paths and available models");
    auto json = std::make_shared<bool>(false);
    cmd->add_flag("--json", *json, "Print JSON");
    cmd->callback([&action, json] {
        action = [json] {
            const nlohmann::json j = {
                {"version", kVersion},
                {"git_commit", kGitCommit},
                {"openfoam_version", MIXLOAD_OPENFOAM_VERSION},
                {"rheology_library", cases::rheologyLibraryPath()},
                {"monitors_library", cases::monitorsLibraryPath()},
                {"models", {"muI", "muIRegularised", "schaeffer"}},
                {"function_objects", {"collapseMonitor"}}};
            if (*json) {
                std::cout << j.dump(2) << '\n';
            } else {
                std::cout << "mixload " << kVersion << " (" << kGitCommit << ")\n"
                          << "OpenFOAM " << MIXLOAD_OPENFOAM_VERSION << "\n"
                          << "rheology library: " << cases::rheologyLibraryPath() << "\n"
                          << "models: muI muIRegularised schaeffer\n";
            }
            return 0;
        };
    });
}

}  // namespace mixload::app
