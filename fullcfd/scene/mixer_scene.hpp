// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/material.hpp"

namespace mixload::scene {

// The scene a mixer command uses when none is named (data/scenes/<name>.toml).
inline constexpr const char* kDefaultMixerScene = "gcm250-v3";
inline constexpr double kSlidingMeshMaxCourant = 0.5;
// The sliding mesh's pcorr solves stop at 1e-3 of their initial residual: fragmentAMI.H repeats
// them until the pairs' continuity error is below 1e-7 anyway (2-3 passes, each limited by the caps'
// partial AMI weights, not by the solve). Against solving each pass to 1e-5 absolute: 24-31% less
// CPU per simulated second on 2 cm (39, 162, 500 rpm), alpha up to 1.000018 instead of 1.0000007,
// the same loading to 1e-6 kg (docs/sliding-mesh.md).
inline constexpr double kSlidingMeshPcorrRelTol = 1e-3;

// Geometry of a Gericke-type continuous horizontal mixer (all lengths in metres). The shaft lies on
// the x axis; the feed end face is x = 0 and the discharge is x = length; gravity is -z.
struct MixerGeometry {
    double length = 0.30, bore = 0.10;
    double shaftDiameter = 0.02;
    int paddleCount = 12;
    double tipClearance = 0.003, paddleWidth = 0.015, paddleThickness = 0.004;
    double pitchDeg = 45, offsetDeg = 90;
    // Angle of the first paddle (0: along +y; gravity is -z). A frozen rotor (MRF) sees the paddles
    // only where they stand, so its loading can depend on this; the sliding mesh turns them.
    double phaseDeg = 0;
    double endGap = 0.004, endClearance = 0.003;
    double weirChordDeg = 20;
    int weirCovers = +1;  // +1: the weir closes the +y half of the discharge, -1: the -y half
    double inletDiameter = 0.02, inletHeight = 0.025;

    void validate() const;  // throws InputError naming the key, also for impossible combinations

    double radius() const { return 0.5 * bore; }
    double shaftRadius() const { return 0.5 * shaftDiameter; }
    double tipRadius() const { return radius() - tipClearance; }
    // The rotating zone: a cylinder halfway between the paddle tips and the bore, from endGap to
    // length - endGap. It holds the whole impeller (shaft section + paddles).
    double rotorRadius() const { return radius() - 0.5 * tipClearance; }
    double rotorX0() const { return endGap; }
    double rotorX1() const { return length - endGap; }
    // Paddle centres are equally spaced over the impeller span inside the zone.
    double impellerX0() const { return endGap + endClearance; }
    double impellerX1() const { return length - endGap - endClearance; }
    double paddleSpacing() const { return (impellerX1() - impellerX0()) / paddleCount; }
    double paddleX(int i) const { return impellerX0() + (i + 0.5) * paddleSpacing(); }
    double paddleAngleDeg(int i) const { return phaseDeg + i * offsetDeg; }
    // Half the axial extent of one pitched paddle.
    double paddleAxialHalf() const;
    // Volume inside the barrel that the powder can occupy (bore minus shaft and paddles).
    double openVolume() const;
};

// Solver settings that set the number and the cost of time steps (README, "Cost of a steady
// point"). `legacy` is what every run before them used; `fast` removes the limits the profile showed
// to be non-physical. Either preset can be adjusted key by key.
struct MixerNumerics {
    std::string preset = "fast";
    double airViscosity = 1.5e-5;  // kinematic viscosity of the air phase [m2/s]
    // The flow and interface Courant limits count only cells with at least this powder fraction
    // (0: every cell, as stock interFoam).
    double courantAlphaMin = 0;
    int nonOrthCorrectors = 1;     // pressure non-orthogonal correctors
    // MULES sub-cycles per step: alpha keeps the scene's Courant limit per sub-cycle while the
    // step (momentum, pressure) runs at this many times that limit.
    int alphaSubCycles = 1;
    double maxDeltaT = 0.01;       // [s]; also at most 1/72 of a revolution

    static MixerNumerics named(const std::string& name);  // legacy | fast
    void validate() const;
    bool sameSettings(const MixerNumerics& o) const;  // every value but the preset's name
};

// A mixer run's inputs: geometry, powder, operating point, method and mesh.
struct MixerScene {
    std::string name = kDefaultMixerScene;
    MixerGeometry geometry;
    Material material;             // grain-side values; bulk density = phi * rhoS
    std::string convention = "paper";
    std::string rheology = "muI";  // muI | muIRegularised | schaeffer
    std::optional<double> etaMax;  // [Pa s]; default Rauter's with H = etaMaxH
    std::optional<double> etaMaxH; // [m] the flow depth H in Rauter's cap; default the bore
    double pMin = 1.0;             // [Pa]
    double rpm = 39, feedKgH = 5, initialLoadingKg = 0.3;
    std::string method = "mrf";    // mrf | lts | sm
    std::string mesh = "coarse";   // coarse | medium | fine | custom
    // ogrid: blockMesh O-grid, smooth bore, rotor zone up to the middle of the tip gap (every
    // method); snappy: castellated snappyHexMesh, zone minus the wall-touching cells (mrf, lts).
    std::string mesher = "ogrid";
    double cellSize = 0.005;       // background cell [m]; the impeller and zone are refined once
    std::array<double, 3> levelCells{0.005, 0.0035, 0.0025};  // coarse, medium, fine from the file
    double endTime = 120;          // cap [s] (lts: pseudo-time iterations are capped separately)
    int ltsIterations = 20000;     // lts cap
    double steadyWindowRevs = 3;   // steady test: window of at least this many revolutions ...
    double steadyResidence = 0.5;  // ... and this share of the residence time M / feed ...
    double steadyTol = 0.02;       // ... consecutive window means within this fraction ...
    double steadyFlowTol = 0.10;   // ... and mean outflow within this fraction of the feed
    double minTime = 0;            // no steady verdict before this time [s]
    double gravity = 9.81;
    double maxCourant = 1.0;       // flow and interface Courant limit (campaign retries halve it)
    MixerNumerics numerics = MixerNumerics::named("fast");

    void validate() const;
    void setMesh(const std::string& level);  // coarse | medium | fine
    // "coarse", or "0.01 m" for an explicit cell size; " snappy" appended for the castellated mesh.
    std::string meshLabel() const;
    double bulkDensity() const { return material.bulkDensity(); }
    double omega() const;          // [rad/s]
    // Powder faster than this has left physics: ten times the paddle tips' speed plus the free-fall
    // speed across the bore [m/s]. The loading monitor stops a run that reaches it.
    double divergedPowderSpeed() const;
    double revolutionTime() const { return rpm > 0 ? 60.0 / rpm : 1e30; }
    // The time step's Courant limit: maxCourant, at most kSlidingMeshMaxCourant for the sliding
    // mesh, whose fragment transport left alpha bounded at 0.5 and not at 1 (-0.011 in 0.5 s on
    // 2 cm; docs/sliding-mesh.md).
    double courantLimit() const;
    double feedKgS() const { return feedKgH / 3600.0; }
    double feedM3S() const { return feedKgS() / bulkDensity(); }
    double etaMaxValue() const;
    double muSCase() const;
    double muDCase() const;
    double steadyWindow() const;   // shortest window [s], or iterations for lts
    // Windows are whole multiples of this [s]: a revolution (0: none, for lts and no rotation).
    double steadyPeriod() const;
    // Windows span at least this share of M / feed (0 for lts: iterations have no residence time).
    double steadyResidenceFraction() const;
    // The window for a loading M [kg] (steady::windowLength with the three settings above).
    double steadyWindow(double loadingKg) const;

    nlohmann::json toJson() const;  // canonical: every input that changes the result
    std::string hash() const;
};

// Numeric keys of the scene file set from outside it ("weir.chord_angle_deg" -> 82), by
// `mixer --set` and by calibrations. They are written into the file's table before it is parsed,
// so they meet the same checks (unknown key, range, whole number) as the file's own values.
using SceneKeys = std::map<std::string, double>;

// Parses a mixer scene TOML (see data/scenes/gcm250.toml); origin names the file in errors.
MixerScene parseMixerScene(const std::string& text, const std::string& origin,
                           const SceneKeys& keys = {});
// A shipped scene by name (data/scenes/<name>.toml) or a path to a .toml file.
MixerScene loadMixerScene(const std::string& nameOrPath, const SceneKeys& keys = {});
// "table.key=value" -> keys (InputError naming the argument if it is not of that form).
void parseSceneKey(const std::string& assignment, SceneKeys& keys);

// Height (z, relative to the axis) of a flat powder surface that holds the given volume in an
// empty bore of radius R and length L (circular segment).
double depositHeight(double volume, double R, double L);

}  // namespace mixload::scene
