// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>

#include "cases/collapse2d.hpp"
#include "common/input_error.hpp"
#include "scene/collapse_scene.hpp"

using namespace mixload;

namespace {
scene::CollapseScene quartz() {
    scene::CollapseScene s;
    s.material = scene::loadMaterial("quartz");
    return s;
}

std::string errorOf(const scene::CollapseScene& s) {
    try {
        s.validate();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}
}  // namespace

TEST(CollapseScene, ShippedMaterialsLoad) {
    const auto q = scene::loadMaterial("quartz");
    EXPECT_EQ(q.grainDensity, 2650.0);
    EXPECT_NEAR(q.bulkDensity(), 0.58 * 2650.0, 1e-9);
    const auto c = scene::loadMaterial("copper");
    EXPECT_EQ(c.muS, 1.22);
    EXPECT_THROW(scene::loadMaterial("sugar"), InputError);
}

TEST(CollapseScene, MeshIsUniformAndHoldsTheRunout) {
    auto s = quartz();
    s.aspect = 2;
    s.cellsPerLength = 30;
    EXPECT_NEAR(s.dx(), 0.05 / 30, 1e-15);
    EXPECT_GE(s.domainWidth(), s.length * (1 + scene::runoutEstimate(2)));
    EXPECT_GT(s.domainHeight(), s.height());
    EXPECT_EQ(s.cells(), static_cast<long>(s.nx()) * s.ny());
}

TEST(CollapseScene, EtaMaxIsRauterUnlessGiven) {
    auto s = quartz();
    EXPECT_NEAR(s.etaMaxValue(), 265.0 * std::sqrt(9.81 * std::pow(0.1, 3)), 1e-9);
    s.etaMax = 12.0;
    EXPECT_EQ(s.etaMaxValue(), 12.0);
}

TEST(CollapseScene, PaperConventionScalesFrictionOnly) {
    auto s = quartz();
    s.convention = "paper";
    EXPECT_NEAR(s.muSCase(), 1.33 / std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(s.muDCase(), 1.69 / std::sqrt(2.0), 1e-12);
}

TEST(CollapseScene, HashIsStableAndSensitive) {
    auto a = quartz(), b = quartz();
    EXPECT_EQ(a.hash(), b.hash());
    b.aspect = 2.5;
    EXPECT_NE(a.hash(), b.hash());
}

TEST(CollapseScene, DenserWritesEnterTheRecordOnlyWhenAsked) {
    // Runs written 4 times per t* keep their hashes; more writes make another run.
    auto a = quartz(), b = quartz();
    EXPECT_FALSE(a.toJson().contains("writes_per_tstar"));
    b.writesPerTstar = 20;
    EXPECT_EQ(b.toJson()["writes_per_tstar"], 20);
    EXPECT_NE(a.hash(), b.hash());
    b.writesPerTstar = 0;
    EXPECT_EQ(errorOf(b), "invalid writes-per-tstar = 0: allowed [1, 200]");
}

TEST(CollapseScene, BadInputNamesKeyValueAndRange) {
    auto s = quartz();
    s.aspect = 12;
    EXPECT_EQ(errorOf(s), "invalid aspect = 12: allowed [0.2, 10]");
    s = quartz();
    s.material.muD = 1.0;  // below mu_s = 1.33
    EXPECT_EQ(errorOf(s), "invalid mu_d = 1: allowed (1.33, 5]");
    s = quartz();
    s.material.grainDiameter = -1e-4;
    EXPECT_EQ(errorOf(s), "invalid grain_diameter_m = -0.0001: allowed (0, 0.01]");
    s = quartz();
    s.rheology = "bingham";
    EXPECT_EQ(errorOf(s), "invalid rheology = bingham: allowed muI|muIRegularised|schaeffer");
}

TEST(CollapseScene, MalformedMaterialTomlIsRejected) {
    EXPECT_THROW(scene::parseMaterialToml("mu_s = = 2", "bad.toml"), InputError);
    EXPECT_THROW(scene::parseMaterialToml("name='x'\ngrain_density_kg_m3=1\n", "short.toml"), InputError);
    try {
        scene::parseMaterialToml(
            "grain_density_kg_m3=2500\ngrain_diameter_m=1e-4\nsolid_fraction=0.6\nmu_s=0.3\n"
            "mu_d=0.5\ni0=0.3\nfriction=1\n",
            "extra.toml");
        FAIL();
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("unknown key friction"), std::string::npos);
    }
}

TEST(CollapseCase, ColumnOverlapIsExact) {
    const double Li = 0.05, Hi = 0.1234, dx = Li / 7;
    double area = 0;
    for (int j = 0; j < 200; ++j)
        for (int i = 0; i < 20; ++i)
            area += cases::columnOverlap(i * dx, (i + 1) * dx, j * dx, (j + 1) * dx, Li, Hi) * dx * dx;
    EXPECT_NEAR(area, Li * Hi, 1e-14);
    EXPECT_DOUBLE_EQ(cases::columnOverlap(0, dx, 0, dx, Li, Hi), 1.0);
    EXPECT_DOUBLE_EQ(cases::columnOverlap(Li, Li + dx, 0, dx, Li, Hi), 0.0);
}
