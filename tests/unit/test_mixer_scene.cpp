// SPDX-License-Identifier: GPL-3.0-or-later
// The mixer scene: shipped file, validation of impossible geometry, generated surfaces, initial bed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>

#include "cases/mixer3d.hpp"
#include "cases/mixer_geometry.hpp"
#include "common/input_error.hpp"
#include "scene/mixer_scene.hpp"

using namespace mixload;
using mixload::scene::MixerScene;

namespace {
constexpr double kPi = std::numbers::pi;

MixerScene parse(const std::string& extra) {
    return scene::parseMixerScene(extra, "test.toml");
}

void expectInvalid(const std::string& toml, const std::string& needle) {
    try {
        parse(toml);
        FAIL() << "accepted: " << toml;
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
}
}  // namespace

TEST(MixerScene, ShippedSceneLoadsWithItsStatedValues) {
    const auto s = scene::loadMixerScene("gcm250");
    EXPECT_EQ(s.geometry.paddleCount, 12);
    EXPECT_DOUBLE_EQ(s.geometry.weirChordDeg, 20.0);
    EXPECT_DOUBLE_EQ(s.rpm, 39.0);
    EXPECT_DOUBLE_EQ(s.feedKgH, 5.0);
    EXPECT_NEAR(s.bulkDensity(), 0.62 * 532.0, 1e-9);
    EXPECT_EQ(s.convention, "paper");
    EXPECT_EQ(s.hash(), scene::loadMixerScene("gcm250").hash());
}

TEST(MixerScene, DefaultSceneCarriesItsNumericsAndSteadyTest) {
    // The calibrated scene differs from gcm250 in geometry and carries the settings it was
    // calibrated with; gcm250 stays as it was (its ledgers' hashes).
    const auto v2 = scene::loadMixerScene(scene::kDefaultMixerScene), v1 = scene::loadMixerScene("gcm250");
    EXPECT_EQ(v2.name, "gcm250-v3");
    EXPECT_DOUBLE_EQ(v2.geometry.paddleThickness, 0.01385);  // what its 1 cm mesh cuts
    EXPECT_DOUBLE_EQ(v2.geometry.bore, 0.165);
    EXPECT_DOUBLE_EQ(v2.geometry.weirChordDeg, 70.0);
    EXPECT_DOUBLE_EQ(v2.geometry.inletHeight, -0.035);
    EXPECT_DOUBLE_EQ(v2.numerics.courantAlphaMin, 0.05);
    EXPECT_DOUBLE_EQ(v2.endTime, 1200.0);
    EXPECT_DOUBLE_EQ(v2.steadyResidence, 0.5);
    EXPECT_DOUBLE_EQ(v2.steadyTol, 0.01);
    EXPECT_DOUBLE_EQ(v2.steadyFlowTol, 0.03);
    EXPECT_DOUBLE_EQ(v2.cellSize, 0.01);
    EXPECT_DOUBLE_EQ(v1.geometry.bore, 0.10);
    EXPECT_DOUBLE_EQ(v1.numerics.courantAlphaMin, 0.0);
    EXPECT_NE(v1.hash(), v2.hash());
}

TEST(MixerScene, HashFollowsEveryInput) {
    auto a = parse(""), b = parse("");
    b.rpm = 162;
    EXPECT_NE(a.hash(), b.hash());
    b = a;
    b.method = "lts";
    EXPECT_NE(a.hash(), b.hash());
}

TEST(MixerScene, OnlyNewSettingsEnterTheHash) {
    // Runs recorded on the snappy mesh with revolutions-only windows keep their hashes.
    auto a = parse("");
    EXPECT_EQ(a.mesher, "ogrid");
    EXPECT_EQ(a.toJson()["mesher"], "ogrid");
    EXPECT_EQ(a.toJson()["steady_window_residence"], 0.5);
    a.mesher = "snappy";
    a.steadyResidence = 0;
    EXPECT_FALSE(a.toJson().contains("mesher"));
    EXPECT_FALSE(a.toJson().contains("steady_window_residence"));
    a.method = "sm";
    EXPECT_THROW(a.validate(), InputError);
    a.mesher = "ogrid";
    EXPECT_FALSE(a.toJson().contains("mesher"));
    expectInvalid("[mesh]\nmesher = \"tet\"\n", "invalid mesher = tet: allowed ogrid|snappy");
}

TEST(MixerScene, NumericsEnterTheRecordOnlyWhenNew) {
    // The default: fast numerics (no non-orthogonal correctors), in the record. Legacy numerics
    // leave no key: old runs keep their hashes.
    auto a = parse("");
    EXPECT_EQ(a.numerics.preset, "fast");
    EXPECT_EQ(a.toJson()["numerics"]["non_orth_correctors"], 0);
    a.numerics = scene::MixerNumerics::named("legacy");
    EXPECT_FALSE(a.toJson().contains("numerics"));
    // The same settings reached key by key hash alike, whatever the preset's name.
    auto b = parse("[numerics]\npreset = \"legacy\"\nnon_orth_correctors = 0\n");
    auto c = parse("");
    EXPECT_EQ(b.toJson()["numerics"], c.toJson()["numerics"]);
    expectInvalid("[numerics]\npreset = \"turbo\"\n", "legacy|fast");
    expectInvalid("[numerics]\nnon_orth_correctors = 0.5\n", "numerics.non_orth_correctors");
    expectInvalid("[numerics]\ncourant_alpha_min = 1.5\n", "courant-alpha-min");
    expectInvalid("[numerics]\nmax_courant = 2\n", "unknown key numerics.max_courant");
    // The castellated mesh needs its non-orthogonal correctors.
    expectInvalid("[mesh]\nmesher = \"snappy\"\n", "non-orth-correctors");
    EXPECT_NO_THROW(parse("[mesh]\nmesher = \"snappy\"\n[numerics]\npreset = \"legacy\"\n"));
}

TEST(MixerScene, RejectsImpossibleGeometry) {
    expectInvalid("[impeller]\npaddle_tip_clearance_m = -0.001\n", "impeller.paddle_tip_clearance_m");
    expectInvalid("[barrel]\nbore_m = 0.05\n[impeller]\nshaft_diameter_m = 0.045\n",
                  "impeller.shaft_diameter_m");
    expectInvalid("[weir]\nchord_angle_deg = 95\n", "invalid weir.chord_angle_deg = 95: allowed (-90, 90)");
    expectInvalid("[weir]\ncovers = \"up\"\n", "weir.covers");
    expectInvalid("[operation]\nfeed_kg_h = -5\n", "invalid feed-kg-h = -5");
    expectInvalid("[impeller]\npaddle_count = 40\n", "impeller.paddle_count");
    expectInvalid("[impeller]\npaddle_count = 2.5\n", "a whole number");
    expectInvalid("[inlet]\nheight_m = 0.001\n", "inlet.height_m");
    expectInvalid("[inlet]\nheight_m = -0.015\n", "inlet.height_m");  // into the shaft
    expectInvalid("[inlet]\nheight_m = -0.045\n", "inlet.height_m");  // through the bore
    EXPECT_DOUBLE_EQ(parse("[inlet]\nheight_m = -0.035\n").geometry.inletHeight, -0.035);  // into the bed
    expectInvalid("[barrel]\nlenght_m = 0.3\n", "unknown key barrel.lenght_m");
    expectInvalid("[rotor]\nx = 1\n", "unknown table [rotor]");
    expectInvalid("[operation]\ninitial_loading_kg = 5\n", "initial-loading-kg");
    expectInvalid("[barrel\n", "malformed TOML");
}

TEST(MixerScene, PaddlesStayInsideTheRotatingZone) {
    const auto g = parse("").geometry;
    const double half = g.paddleAxialHalf();
    EXPECT_GE(g.paddleX(0) - half, g.rotorX0());
    EXPECT_LE(g.paddleX(g.paddleCount - 1) + half, g.rotorX1());
    EXPECT_GT(g.rotorRadius(), g.tipRadius());
    EXPECT_LT(g.rotorRadius(), g.radius());
}

TEST(MixerScene, DepositHeightHoldsTheVolume) {
    const double R = 0.05, L = 0.3;
    EXPECT_NEAR(scene::depositHeight(0.5 * kPi * R * R * L, R, L), 0.0, 1e-9);  // half full
    EXPECT_NEAR(scene::depositHeight(kPi * R * R * L, R, L), R, 1e-9);
    // A thin segment: area ~ (4/3) sqrt(2R) h^(3/2).
    const double h = 1e-3;
    const double area = R * R * std::acos(1 - h / R) - (R - h) * std::sqrt(2 * R * h - h * h);
    EXPECT_NEAR(scene::depositHeight(area * L, R, L), -R + h, 1e-9);
}

TEST(MixerGeometry, DischargeIsSplitInHalvesAndPortsHaveTheirArea) {
    const auto g = parse("").geometry;
    const auto barrel = cases::barrelSurface(g);
    const double disc = kPi * g.radius() * g.radius();
    // Polygonal discs: within the 96-sector chord error.
    EXPECT_NEAR(barrel.area("outlet"), 0.5 * disc, 0.002 * disc);
    EXPECT_NEAR(barrel.area("weir"), 0.5 * disc, 0.002 * disc);
    const double port = 0.25 * kPi * g.inletDiameter * g.inletDiameter;
    EXPECT_NEAR(barrel.area("inlet"), port, 0.08 * port);  // triangles assigned by centroid
    EXPECT_NEAR(barrel.area("wall"), 2 * kPi * g.radius() * g.length + disc - port,
                0.01 * (2 * kPi * g.radius() * g.length));
    // The weir closes the bottom of the discharge (chord 20 degrees from vertical, +y side).
    EXPECT_TRUE(cases::onWeir(g, 0.0, -g.radius()));
    EXPECT_FALSE(cases::onWeir(g, -0.5 * g.radius(), 0.0));
}

TEST(MixerGeometry, PaddleBoxesHaveTheirArea) {
    const auto g = parse("").geometry;
    const auto p = cases::paddleSurface(g);
    const double l = g.tipRadius() - 0.5 * g.shaftRadius();
    const double one = 2 * (l * g.paddleWidth + l * g.paddleThickness + g.paddleWidth * g.paddleThickness);
    EXPECT_NEAR(p.area("paddles"), g.paddleCount * one, 1e-9);
}

TEST(MixerScene, KeysSetFromOutsideMeetTheFilesChecks) {
    const auto base = scene::loadMixerScene("gcm250");
    const auto s = scene::loadMixerScene("gcm250", {{"weir.chord_angle_deg", 70}, {"impeller.paddle_count", 6}});
    EXPECT_DOUBLE_EQ(s.geometry.weirChordDeg, 70.0);
    EXPECT_EQ(s.geometry.paddleCount, 6);
    EXPECT_NE(s.hash(), base.hash());
    // A table the file does not have is created.
    EXPECT_DOUBLE_EQ(parse("").geometry.weirChordDeg, 20.0);
    EXPECT_DOUBLE_EQ(scene::parseMixerScene("", "t.toml", {{"weir.chord_angle_deg", 45}}).geometry.weirChordDeg, 45.0);
    const auto refused = [](const scene::SceneKeys& k, const std::string& needle) {
        try {
            scene::loadMixerScene("gcm250", k);
            ADD_FAILURE() << needle;
        } catch (const InputError& e) {
            EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
        }
    };
    refused({{"weir.chord", 45}}, "weir.chord");
    refused({{"weir.chord_angle_deg", 95}}, "weir.chord_angle_deg");
    refused({{"impeller.paddle_count", 2.5}}, "whole number");
    refused({{"chord_angle_deg", 45}}, "TABLE.KEY");
    refused({{"nosuch.key", 45}}, "TABLE.KEY");
    scene::SceneKeys k;
    scene::parseSceneKey("weir.chord_angle_deg=70", k);
    EXPECT_DOUBLE_EQ(k.at("weir.chord_angle_deg"), 70.0);
    EXPECT_THROW(scene::parseSceneKey("weir.chord_angle_deg=7O", k), InputError);
    EXPECT_THROW(scene::parseSceneKey("weir.chord_angle_deg", k), InputError);
}

TEST(MixerScene, TheViscosityCapsDepthIsAKeyOfTheScene) {
    const auto base = scene::loadMixerScene("gcm250");
    const auto s = scene::loadMixerScene("gcm250", {{"powder.eta_max_h_m", 1.0}});
    // Rauter's cap grows as H^3/2: ten bores, about 31.6 times the cap.
    EXPECT_NEAR(s.etaMaxValue() / base.etaMaxValue(), std::pow(10.0, 1.5), 1e-9);
    EXPECT_NE(s.hash(), base.hash());
    EXPECT_THROW(scene::loadMixerScene("gcm250", {{"powder.eta_max_h_m", -1}}), InputError);
}

TEST(MixerScene, TheSteadyTestCanBelongToTheScene) {
    const auto s = parse("[steady]\nend_time_s = 900\ntol = 0.01\nflow_tol = 0.03\nwindow_residence = 0.25\n");
    EXPECT_DOUBLE_EQ(s.endTime, 900);
    EXPECT_DOUBLE_EQ(s.steadyTol, 0.01);
    EXPECT_DOUBLE_EQ(s.steadyFlowTol, 0.03);
    EXPECT_DOUBLE_EQ(s.steadyResidence, 0.25);
    EXPECT_NE(s.hash(), parse("").hash());
    expectInvalid("[steady]\nwindow = 3\n", "steady.window");
    expectInvalid("[steady]\ntol = 0.9\n", "steady-tol");
    // Without the table the defaults, and the shipped scene's hash, stay.
    EXPECT_DOUBLE_EQ(parse("").endTime, MixerScene{}.endTime);
}

TEST(MixerScene, SlidingMeshRunsTheFragmentTransport) {
    // Issue 17: sm cases carry their AMI pairs per overlap fragment, on the explicit MULES path
    // with one corrector and a Courant limit of at most 0.5; the record says so, so that results of
    // the leaking sm are not taken for today's. MRF cases are unchanged.
    auto mrf = parse("");
    auto sm = mrf;
    sm.method = "sm";
    EXPECT_FALSE(mrf.toJson().contains("sm_transport"));
    EXPECT_EQ(sm.toJson()["sm_transport"], "fragments-kmax");
    EXPECT_DOUBLE_EQ(mrf.courantLimit(), mrf.maxCourant);
    EXPECT_DOUBLE_EQ(sm.courantLimit(), std::min(sm.maxCourant, scene::kSlidingMeshMaxCourant));
    sm.maxCourant = 0.25;
    EXPECT_DOUBLE_EQ(sm.courantLimit(), 0.25);

    const auto read = [](const std::filesystem::path& f) {
        std::ifstream in(f);
        return std::string(std::istreambuf_iterator<char>(in), {});
    };
    const auto dir = std::filesystem::temp_directory_path() / "mixload-unit-sm-case";
    std::filesystem::remove_all(dir);
    cases::writeMixerMeshCase(sm, dir / "sm", 1);
    cases::writeMixerMeshCase(mrf, dir / "mrf", 1);
    const std::string smSol = read(dir / "sm/system/fvSolution");
    const std::string mrfSol = read(dir / "mrf/system/fvSolution");
    EXPECT_NE(smSol.find("fragmentAMI yes;"), std::string::npos);
    EXPECT_NE(smSol.find("MULESCorr no;"), std::string::npos);
    EXPECT_NE(smSol.find("nAlphaCorr 1;"), std::string::npos);
    EXPECT_EQ(mrfSol.find("fragmentAMI"), std::string::npos);
    EXPECT_NE(mrfSol.find("MULESCorr yes;"), std::string::npos);
    // pcorr passes stop at 1e-3 of their residual on the sliding mesh (it repeats them); MRF's
    // single solve keeps relTol 0. The record says so.
    EXPECT_NE(smSol.find("tolerance 1e-5; relTol 0.001; }"), std::string::npos) << smSol;
    EXPECT_NE(mrfSol.find("tolerance 1e-5; relTol 0; }"), std::string::npos);
    EXPECT_DOUBLE_EQ(sm.toJson()["sm_pcorr_rel_tol"].get<double>(), scene::kSlidingMeshPcorrRelTol);
    EXPECT_NE(read(dir / "sm/system/controlDict").find("maxCo 0.25;"), std::string::npos);
    std::filesystem::remove_all(dir);
}

TEST(MixerScene, ThePaddlesPhaseTurnsTheFrozenRotorAndEntersTheHashOnlyWhenSet) {
    // Runs recorded before the key existed had phase 0 and keep their hashes.
    const auto base = scene::loadMixerScene("gcm250-v2");
    EXPECT_FALSE(base.toJson()["geometry"].contains("paddle_phase_deg"));
    EXPECT_EQ(scene::loadMixerScene("gcm250-v2", {{"impeller.paddle_phase_deg", 0}}).hash(), base.hash());
    const auto turned = scene::loadMixerScene("gcm250-v2", {{"impeller.paddle_phase_deg", 45}});
    EXPECT_NE(turned.hash(), base.hash());
    EXPECT_DOUBLE_EQ(turned.toJson()["geometry"]["paddle_phase_deg"].get<double>(), 45.0);
    // Every paddle turns by the phase about the axis: same axial position and radius.
    for (int i = 0; i < base.geometry.paddleCount; ++i) {
        const auto a = cases::paddleBox(base.geometry, i, base.geometry.paddleThickness).centre;
        const auto b = cases::paddleBox(turned.geometry, i, base.geometry.paddleThickness).centre;
        const double phiA = std::atan2(a[2], a[1]), phiB = std::atan2(b[2], b[1]);
        EXPECT_NEAR(b[0], a[0], 1e-12);
        EXPECT_NEAR(std::hypot(b[1], b[2]), std::hypot(a[1], a[2]), 1e-12);
        EXPECT_NEAR(std::remainder(phiB - phiA, 2 * kPi), kPi / 4, 1e-12);
    }
    try {
        scene::loadMixerScene("gcm250-v2", {{"impeller.paddle_phase_deg", 400}});
        ADD_FAILURE() << "accepted a phase of 400 degrees";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("impeller.paddle_phase_deg"), std::string::npos) << e.what();
    }
}
