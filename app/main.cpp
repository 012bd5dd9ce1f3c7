// SPDX-License-Identifier: GPL-3.0-or-later
// mixload: one executable, one subcommand per user task. Exit codes: 0 success, 1 a run failed,
// 2 bad input (nothing written).
#include <iostream>

#include "app/commands.hpp"
#include "common/input_error.hpp"
#include "run/foam_runner.hpp"

int main(int argc, char** argv) {
    CLI::App app{"mixload: powder flow and loading of continuous horizontal mixers"};
    app.require_subcommand(1);
    mixload::app::Action action;
    mixload::app::addInfo(app, action);
    mixload::app::addCollapse(app, action);
    mixload::app::addMixer(app, action);
    mixload::app::addSnapshots(app, action);
    mixload::app::addRom(app, action);
    mixload::app::addPredict(app, action);
    mixload::app::addSurrogate(app, action);
    mixload::app::addBench(app, action);
    mixload::app::addStudy(app, action);
    mixload::app::addCampaign(app, action);
    mixload::app::addCalibrate(app, action);
    mixload::app::addSensitivity(app, action);
    mixload::app::addPlane(app, action);
    mixload::app::addStress(app, action);
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : 2;
    }
    try {
        return action ? action() : 0;
    } catch (const mixload::InputError& e) {
        std::cerr << "mixload: " << e.what() << '\n';
        return 2;
    } catch (const mixload::run::RunError& e) {
        std::cerr << "mixload: run failed: " << e.what() << '\n';
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "mixload: error: " << e.what() << '\n';
        return 1;
    }
}
