// SPDX-License-Identifier: GPL-3.0-or-later
// Bad input: exit code 2, one message naming key, value and allowed range, nothing left behind.
#include <gtest/gtest.h>

#include <fstream>

#include "cli_harness.hpp"

using namespace mixload::testing;
namespace fs = std::filesystem;

namespace {
void expectRejected(std::vector<std::string> args, const std::string& needle) {
    mixload::testing::expectRejected("collapse", std::move(args), needle);
}
}  // namespace

TEST(CliErrors, MuDBelowMuS) {
    expectRejected({"--mu-s", "0.5", "--mu-d", "0.4"}, "invalid mu_d = 0.4: allowed (0.5, 5]");
}

TEST(CliErrors, NonPositiveI0) { expectRejected({"--i0", "0"}, "invalid i0 = 0: allowed (0, 10]"); }

TEST(CliErrors, AspectOutOfRange) {
    expectRejected({"--aspect", "0.1"}, "invalid aspect = 0.1: allowed [0.2, 10]");
    expectRejected({"--aspect", "11"}, "invalid aspect = 11: allowed [0.2, 10]");
}

TEST(CliErrors, UnknownMaterial) {
    expectRejected({"--material", "sugar"}, "invalid material = sugar: allowed ");
}

TEST(CliErrors, NonPositiveDiameterAndDensityInMaterialFile) {
    const fs::path dir = scratchDir("materials");
    std::ofstream(dir / "neg_d.toml") << "grain_density_kg_m3 = 2500\ngrain_diameter_m = -1e-4\n"
                                         "solid_fraction = 0.6\nmu_s = 0.3\nmu_d = 0.5\ni0 = 0.3\n";
    std::ofstream(dir / "zero_rho.toml") << "grain_density_kg_m3 = 0\ngrain_diameter_m = 1e-4\n"
                                            "solid_fraction = 0.6\nmu_s = 0.3\nmu_d = 0.5\ni0 = 0.3\n";
    expectRejected({"--material", (dir / "neg_d.toml").string()},
                   "invalid grain_diameter_m = -0.0001: allowed (0, 0.01]");
    expectRejected({"--material", (dir / "zero_rho.toml").string()},
                   "invalid grain_density_kg_m3 = 0: allowed (0, 25000]");
}

TEST(CliErrors, MalformedToml) {
    const fs::path dir = scratchDir("materials-bad");
    std::ofstream(dir / "broken.toml") << "grain_density_kg_m3 = [2500\n";
    expectRejected({"--material", (dir / "broken.toml").string()}, "malformed TOML");
}

TEST(CliErrors, UnknownRheology) {
    expectRejected({"--rheology", "bingham"}, "invalid rheology = bingham");
}
