// SPDX-License-Identifier: GPL-3.0-or-later
// A tiny real collapse (quartz, a = 2, dx = Li/10) through the real interFoam and mixload's
// rheology and monitor libraries, serial and on 2 MPI ranks.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"

using namespace mixload::testing;
namespace fs = std::filesystem;

namespace {
nlohmann::json runTiny(int np) {
    const fs::path out = scratchDir("tiny-np" + std::to_string(np)) / "run";
    const auto r = runMixload({"collapse", "--material", "quartz", "--aspect", "2",
                               "--cells-per-length", "10", "--np", std::to_string(np), "--out",
                               out.string(), "--json"});
    EXPECT_EQ(r.rc, 0) << r.err;
    return r.rc == 0 ? nlohmann::json::parse(r.out) : nlohmann::json{};
}

// One serial run per test process, shared by the tests in it; a failed run fails every test
// (it must never turn into a skip).
class TinyCollapse : public ::testing::Test {
protected:
    void SetUp() override {
        static const nlohmann::json serial = runTiny(1);
        serial_ = &serial;
        ASSERT_FALSE(serial.is_null()) << "the serial tiny collapse failed";
    }
    const nlohmann::json* serial_ = nullptr;
};
}  // namespace

TEST_F(TinyCollapse, ReportsEveryField) {
    const auto& r = *serial_;
    for (const char* k : {"runout_star", "height_star", "t_star", "end_time", "stopped_by",
                          "powder_mass_error", "cells", "wall_seconds", "runout_history"})
        EXPECT_TRUE(r.contains(k)) << k;
    EXPECT_NEAR(r["t_star"].get<double>(), std::sqrt(0.1 / 9.81), 1e-9);
    EXPECT_TRUE(fs::exists(r["plot"].get<std::string>()));
}

TEST_F(TinyCollapse, ConservesPowder) {
    EXPECT_LT(std::abs((*serial_)["powder_mass_error"].get<double>()), 1e-3);
    EXPECT_LT((*serial_)["powder_mass_error_max"].get<double>(), 1e-3);
    EXPECT_FALSE((*serial_)["powder_reached_domain_end"].get<bool>());
}

TEST_F(TinyCollapse, SpreadsMonotonicallyAndComesToRest) {
    const auto& r = *serial_;
    EXPECT_EQ(r["stopped_by"], "rest");
    const auto& h = r["runout_history"];
    ASSERT_GT(h.size(), 10u);
    double prev = -1e9;
    for (const auto& p : h) {
        // The front may wobble by a fraction of a cell (dx = Li/10: 0.1 in L*).
        EXPECT_GE(p[1].get<double>(), prev - 0.05) << "at t/t* = " << p[0];
        prev = std::max(prev, p[1].get<double>());
    }
    EXPECT_GT(r["runout_star"].get<double>(), 0.1);  // it did collapse
    EXPECT_GT(r["height_star"].get<double>(), 0.0);
    EXPECT_LE(r["height_star"].get<double>(), 1.0);
    EXPECT_GE(r["end_time"].get<double>(), r["t_star"].get<double>());
}

TEST_F(TinyCollapse, TwoRanksAgreeWithSerial) {
    const auto par = runTiny(2);
    ASSERT_FALSE(par.is_null());
    const double ls = (*serial_)["runout_star"].get<double>();
    const double lp = par["runout_star"].get<double>();
    EXPECT_NEAR(lp, ls, 0.02 * std::abs(ls)) << "serial " << ls << " vs np=2 " << lp;
    EXPECT_EQ(par["stopped_by"], "rest");
}
