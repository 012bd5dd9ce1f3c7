// SPDX-License-Identifier: GPL-3.0-or-later
#include "cases/mixer3d.hpp"

#include <cmath>
#include <sstream>

#include "cases/foam_dict.hpp"
#include "cases/foam_numerics.hpp"
#include "cases/mixer_geometry.hpp"
#include "cases/mixer_ogrid.hpp"

namespace mixload::cases {

namespace {

namespace fs = std::filesystem;

bool onOGrid(const scene::MixerScene& s) { return s.mesher == "ogrid"; }

std::string vec(double x, double y, double z) {
    return "(" + num(x) + " " + num(y) + " " + num(z) + ")";
}

std::string blockMeshDict(const scene::MixerScene& s) {
    const auto& g = s.geometry;
    const double h = s.cellSize;
    // Background box one cell and a bit beyond the barrel, so that snapping never meets its faces.
    const double m = 1.37 * h;
    const double x0 = -m, x1 = g.length + m, r = g.radius() + m;
    const int nx = static_cast<int>(std::ceil((x1 - x0) / h));
    const int ny = static_cast<int>(std::ceil(2 * r / h));
    std::ostringstream os;
    os << "convertToMeters 1;\n\nvertices\n(\n"
       << "    " << vec(x0, -r, -r) << ' ' << vec(x1, -r, -r) << ' ' << vec(x1, r, -r) << ' '
       << vec(x0, r, -r) << '\n'
       << "    " << vec(x0, -r, r) << ' ' << vec(x1, -r, r) << ' ' << vec(x1, r, r) << ' '
       << vec(x0, r, r) << "\n);\n\n"
       << "blocks\n(\n    hex (0 1 2 3 4 5 6 7) (" << nx << ' ' << ny << ' ' << ny
       << ") simpleGrading (1 1 1)\n);\n\nedges ();\n\n"
       << "boundary\n(\n    background { type wall; faces ((0 4 7 3) (1 2 6 5) (0 1 5 4) (3 7 6 2) "
          "(0 3 2 1) (4 5 6 7)); }\n);\n";
    return os.str();
}

std::string snappyHexMeshDict(const scene::MixerScene& s) {
    const auto& g = s.geometry;
    // A point in the powder space: between the first two paddles, below the axis, off the shaft.
    const double xIn = 0.5 * (g.paddleX(0) + g.paddleX(1));
    const double zIn = -0.5 * (g.shaftRadius() + g.rotorRadius()) - 0.1234 * s.cellSize;
    const double yIn = 0.0917 * s.cellSize;
    std::ostringstream os;
    // Walls stay castellated (stair-stepped hexahedra), the mesh every mrf/lts figure in the README
    // was measured on. Snapped meshes blew up with Debian's -O3 interFoam (README, "Why mixload
    // builds its own interFoam") and have not been retried with mixload's build.
    // The frozen-rotor zone needs no conforming boundary: topoSet picks its cells (topoSetDict).
    os << "castellatedMesh true;\nsnap false;\naddLayers false;\n\n"
       << "geometry\n{\n"
       << "    barrel.stl { type triSurfaceMesh; name barrel;\n"
       << "        regions { wall { name wall; } inlet { name inlet; } outlet { name outlet; } "
          "weir { name weir; } } }\n"
       << "    shaft.stl { type triSurfaceMesh; name shaft; }\n"
       << "    paddles.stl { type triSurfaceMesh; name paddles; }\n}\n\n"
       << "castellatedMeshControls\n{\n"
       << "    maxLocalCells 2000000;\n    maxGlobalCells 20000000;\n    minRefinementCells 0;\n"
       << "    maxLoadUnbalance 0.10;\n    nCellsBetweenLevels 2;\n    features ();\n"
       << "    refinementSurfaces\n    {\n"
       << "        barrel\n        {\n            level (0 0);\n"
       << "            patchInfo { type wall; }\n"
       << "            regions\n            {\n"
       << "                inlet { level (0 0); patchInfo { type patch; } }\n"
       << "                outlet { level (0 0); patchInfo { type patch; } }\n"
       << "                weir { level (0 0); patchInfo { type wall; } }\n"
       << "            }\n        }\n"
       << "        shaft { level (0 0); patchInfo { type wall; } }\n"
       // One level finer on the paddles: about one background cell thick.
       << "        paddles { level (1 1); patchInfo { type wall; } }\n"
       << "    }\n    resolveFeatureAngle 30;\n    refinementRegions {}\n"
       << "    locationInMesh " << vec(xIn, yIn, zIn) << ";\n"
       << "    allowFreeStandingZoneFaces true;\n}\n\n"
       << "snapControls\n{\n    nSmoothPatch 3;\n    tolerance 2.0;\n    nSolveIter 50;\n"
       << "    nRelaxIter 5;\n    nFeatureSnapIter 10;\n    implicitFeatureSnap true;\n"
       << "    explicitFeatureSnap false;\n    multiRegionFeatureSnap false;\n}\n\n"
       << "addLayersControls\n{\n    relativeSizes true;\n    layers {}\n    expansionRatio 1.0;\n"
       << "    finalLayerThickness 0.3;\n    minThickness 0.1;\n    nGrow 0;\n    featureAngle 60;\n"
       << "    nRelaxIter 3;\n    nSmoothSurfaceNormals 1;\n    nSmoothNormals 3;\n"
       << "    nSmoothThickness 10;\n    maxFaceThicknessRatio 0.5;\n"
       << "    maxThicknessToMedialRatio 0.3;\n    minMedialAxisAngle 90;\n"
       << "    nBufferCellsNoExtrude 0;\n    nLayerIter 50;\n}\n\n"
       // Stricter than snappy's defaults (a high minimum cell determinant), kept from the time
       // snapped cells were suspected of the blow-ups that Debian's solver binary caused.
       << "meshQualityControls\n{\n    maxNonOrtho 60;\n    maxBoundarySkewness 20;\n"
       << "    maxInternalSkewness 4;\n    maxConcave 80;\n    minVol 1e-13;\n"
       << "    minTetQuality 1e-9;\n    minArea -1;\n    minTwist 0.05;\n"
       << "    minDeterminant 0.2;\n    minFaceWeight 0.1;\n    minVolRatio 0.05;\n"
       << "    minTriangleTwist -1;\n    nSmoothScale 4;\n    errorReduction 0.75;\n"
       << "    relaxed { maxNonOrtho 65; }\n}\n\n"
       << "mergeTolerance 1e-6;\n";
    return os.str();
}

// MRF zone: the cells whose centres lie inside the rotor cylinder, minus every cell that touches a
// stationary boundary. MRF makes the flux relative on such faces (phi -= (omega x r).S), and on a
// stair-stepped bore (omega x r).S is not zero: powder would leak through the wall. Measured on the
// coarse mesh: a mass of 19% of the initial loading unaccounted for after 1 s before this
// exclusion; a balance error of 1e-6 of the loading after it (0.3 s).
std::string topoSetDict(const scene::MixerScene& s) {
    const auto& g = s.geometry;
    return "actions\n(\n    { name rotorCells; type cellSet; action new; source cylinderToCell; p1 " +
           vec(g.rotorX0(), 0, 0) + "; p2 " + vec(g.rotorX1(), 0, 0) + "; radius " +
           num(g.rotorRadius()) + "; }\n" +
           "    { name stillFaces; type faceSet; action new; source patchToFace; "
           "patch \"(wall|inlet|outlet|weir)\"; }\n"
           "    { name rotorCells; type cellSet; action subtract; source faceToCell; "
           "set stillFaces; option any; }\n"
           "    { name rotor; type cellZoneSet; action new; source setToCellZone; set rotorCells; }\n);\n";
}

std::string rotationAxis() { return "origin (0 0 0);\naxis (1 0 0);\n"; }

std::string controlDict(const scene::MixerScene& s, bool keepAllTimes, bool profile, double timeOffset) {
    const bool lts = s.method == "lts";
    std::ostringstream os;
    os << "application interFoam;\nlibs (" << mixloadFoamLibs() << ");\n"
       << "startFrom latestTime;\nstartTime 0;\nstopAt endTime;\n";
    if (lts) {
        // Pseudo-time: one unit per iteration; the monitor ends the run once the loading is steady.
        os << "endTime " << s.ltsIterations << ";\ndeltaT 1;\nwriteControl timeStep;\n"
           << "writeInterval 500;\n";
    } else {
        os << "endTime " << num(timeOffset + s.endTime) << ";  // cap only: the monitor ends the run when steady\n"
           << "deltaT 1e-4;\nwriteControl adjustable;\nwriteInterval "
           << num(std::min(5.0, std::max(0.5, s.revolutionTime()))) << ";\n"
           // Courant 1 by default (semi-implicit MULES): on the tiny mesh, 1 s of flow in 26 s
           // instead of 41 s at 0.5, loading at 1 s within 0.07%, balance -6e-7 kg.
           << "adjustTimeStep yes;\nmaxCo " << num(s.courantLimit() * s.numerics.alphaSubCycles)
           << ";\nmaxAlphaCo " << num(s.courantLimit() * s.numerics.alphaSubCycles) << ";\nmaxDeltaT "
           << num(std::min(s.numerics.maxDeltaT, s.revolutionTime() / 72.0)) << ";\n";
    }
    // Only the last few times are needed to resume; snapshot export wants every written time.
    // OpenFOAM's own profiler (per stage: mixloadInterFoam adds scopes) and the Courant probe:
    // the run's profile (post/run_profile) reads both.
    if (profile)
        os << "profiling { active true; cpuInfo false; memInfo false; sysInfo false; }\n";
    os << "purgeWrite " << (keepAllTimes ? 0 : 3) << ";\nwriteFormat binary;\nwritePrecision 10;\nwriteCompression off;\n"
       << "timeFormat general;\ntimePrecision 10;\nrunTimeModifiable yes;\n\n"
       << "functions\n{\n    " << kLoadingMonitor << "\n    {\n"
       << "        type loadingMonitor;\n        alpha alpha.powder;\n"
       << "        rho " << num(s.bulkDensity()) << ";\n"
       << "        inletPatches (inlet);\n        outletPatches (outlet);\n"
       << "        feed " << num(s.feedKgS()) << ";  // kg/s\n"
       << "        window " << num(s.steadyWindow()) << ";\n"
       << "        period " << num(s.steadyPeriod()) << ";\n"
       << "        residenceFraction " << num(s.steadyResidenceFraction()) << ";\n"
       << "        tolerance " << num(s.steadyTol) << ";\n"
       << "        flowTolerance " << num(s.steadyFlowTol) << ";\n"
       << "        minTime " << num(timeOffset + s.minTime) << ";\n"
       << "        maxPowderSpeed " << num(s.divergedPowderSpeed()) << ";  // m/s: above it the run has diverged\n"
       << "        pseudoTime " << (lts ? "yes" : "no") << ";\n"
       << "        zone rotor;\n"
       << "        writeControl writeTime;\n    }\n";
    if (profile)
        os << "    " << kCourantProfile << "\n    {\n        type courantProfile;\n"
           << "        alpha alpha.powder;\n        zone rotor;\n    }\n";
    os << "}\n";
    return os.str();
}

std::string fvSchemes(const scene::MixerScene& s) {
    // snappy meshes are non-orthogonal near the walls: limited corrections keep the Laplacians
    // bounded. The stress term is explicit, hence the momentum predictor (see fvSolution).
    return std::string("ddtSchemes { default ") + (s.method == "lts" ? "localEuler" : "Euler") +
           "; }\n"
           "gradSchemes { default Gauss linear; }\n"
           "divSchemes\n{\n"
           "    div(rhoPhi,U) Gauss linearUpwindV grad(U);\n"
           "    div(phi,alpha) Gauss vanLeer;\n"
           "    div(phirb,alpha) Gauss linear;\n"
           "    div(((rho*nuEff)*dev2(T(grad(U))))) Gauss linear;\n}\n"
           "laplacianSchemes { default Gauss linear limited corrected 0.5; }\n"
           "interpolationSchemes { default linear; }\n"
           "snGradSchemes { default limited corrected 0.5; }\n";
}

// The momentum matrix carries the capped granular viscosity: diffusion-dominated, on which
// Gauss-Seidel sweeps converge slowly (25-33 sweeps per component and step on gcm250-v2's bed) and
// DILU-preconditioned BiCGStab in 5-6 iterations. Both solve to the same tolerance, so the choice
// is not part of a scene's identity (its hash): 150 steps of the calibrated bed gave the same
// loading to 3.6e-8 with either, in 17% less wall time (README, "Cost of a steady point").
std::string momentumSolver(const scene::MixerNumerics& n) {
    return n.preset == "legacy" ? "solver smoothSolver; smoother symGaussSeidel;" : "solver PBiCGStab; preconditioner DILU;";
}

// The O-grid's non-orthogonality is about 1e-6 degrees: its corrections vanish, and with
// numerics.non_orth_correctors 0 the pressure equation is solved once per corrector.
// The sliding mesh carries its AMI pairs per overlap fragment (fragmentAMI.H), which conserves
// powder across them; it stays bounded on the explicit MULES path with one alpha corrector (two
// took alpha to -0.064 in 0.5 s on 2 cm) and the Courant limit of MixerScene::courantLimit.
std::string fvSolution(const scene::MixerScene& s) {
    const bool sm = s.method == "sm";
    std::ostringstream os;
    os << "solvers\n{\n"
       << "    \"alpha.powder.*\"\n    {\n"
       << "        nAlphaCorr " << (sm ? 1 : 2) << "; nAlphaSubCycles "
       << (s.method == "lts" ? 1 : s.numerics.alphaSubCycles) << "; cAlpha 1; MULESCorr "
       << (sm ? "no" : "yes") << "; nLimiterIter 5;\n"
       << "        solver smoothSolver; smoother symGaussSeidel; tolerance 1e-8; relTol 0;\n    }\n"
       << "    \"pcorr.*\" { solver PCG; preconditioner DIC; tolerance 1e-5; relTol "
       << (sm ? num(scene::kSlidingMeshPcorrRelTol) : std::string("0")) << "; }\n"
       // GAMG's agglomerated AMI pairs did not converge on the sliding mesh (1 000 iterations
       // at every final corrector, 2 cm); conjugate gradients do, in 2.5 times less wall time.
       << "    p_rgh { solver " << (sm ? "PCG; preconditioner DIC;" : "GAMG; smoother DIC;")
       << " tolerance 1e-7; relTol 0.05; }\n"
       << "    p_rghFinal { $p_rgh; relTol 0; }\n"
       << "    \"U.*\" { " << momentumSolver(s.numerics) << " tolerance 1e-7; relTol 0; }\n"
       << "}\n\nPIMPLE\n{\n    momentumPredictor yes;\n    nOuterCorrectors 1;\n"
       << "    nCorrectors 2;\n    nNonOrthogonalCorrectors " << s.numerics.nonOrthCorrectors
       << ";\n    courantAlphaMin " << num(s.numerics.courantAlphaMin) << ";\n"
       << "    correctPhi " << (sm ? "yes" : "no") << ";\n"
       << (sm ? "    fragmentAMI yes;\n" : "")
       << "    moveMeshOuterCorrectors no;\n";
    if (s.method == "lts") {
        os << "    maxCo 2;\n    maxAlphaCo 1;\n    rDeltaTSmoothingCoeff 0.05;\n"
           << "    rDeltaTDampingCoeff 0.5;\n    nAlphaSpreadIter 0;\n    nAlphaSweepIter 0;\n"
           << "    maxDeltaT " << num(std::min(0.05, s.revolutionTime() / 36.0)) << ";\n";
    }
    os << "}\n\nrelaxationFactors { equations { \".*\" 1; } }\n";
    return os.str();
}

std::string transportProperties(const scene::MixerScene& s) {
    const auto& m = s.material;
    return cases::transportProperties({s.rheology, s.bulkDensity(), s.muSCase(), s.muDCase(), m.I0,
                                        m.grainDiameter, m.grainDensity, s.etaMaxValue(), s.pMin,
                                        s.numerics.airViscosity});
}

std::string mrfProperties(const scene::MixerScene& s) {
    // No zone cell touches these patches (O-grid: the zone ends in the tip gap and short of the
    // end faces; snappy: topoSetDict leaves such cells out); listing them keeps them still should
    // a zone ever touch them.
    return "MRF1\n{\n    cellZone rotor;\n    active yes;\n"
           "    nonRotatingPatches (wall inlet outlet weir);\n    " +
           rotationAxis() + "    omega " + num(s.omega()) + ";\n}\n";
}

std::string dynamicMeshDict(const scene::MixerScene& s) {
    if (s.method != "sm") return "dynamicFvMesh staticFvMesh;\n";
    return "dynamicFvMesh dynamicMotionSolverFvMesh;\nmotionSolverLibs (fvMotionSolvers);\n"
           "motionSolver solidBody;\ncellZone rotor;\nsolidBodyMotionFunction rotatingMotion;\n" +
           rotationAxis() + "omega " + num(s.omega()) + ";\n";
}

// The boundaryField of a field: one entry per patch kind (the weir takes the wall's). The O-grid
// adds the shaft's stubs in the stationary end layers, the sliding mesh also the AMI pairs.
std::string boundary(const scene::MixerScene& s, const std::string& walls, const std::string& inlet,
                     const std::string& outlet, const std::string& shaft,
                     const std::string& paddles, const std::string& shaftEnds) {
    std::ostringstream os;
    os << "boundaryField\n{\n"
       << "    wall { " << walls << " }\n    weir { " << walls << " }\n"
       << "    inlet { " << inlet << " }\n    outlet { " << outlet << " }\n"
       << "    shaft { " << shaft << " }\n    paddles { " << paddles << " }\n";
    if (onOGrid(s)) os << "    shaftEnds { " << shaftEnds << " }\n";
    if (s.method == "sm") os << "    \"AMI.*\" { type cyclicAMI; value $internalField; }\n";
    os << "}\n";
    return os.str();
}

std::string rotatingWall(const scene::MixerScene& s) {
    return "type rotatingWallVelocity; origin (0 0 0); axis (1 0 0); omega " + num(s.omega()) +
           "; value uniform (0 0 0);";
}

void writeFields(const scene::MixerScene& s, const fs::path& dir) {
    const std::string zg = "type zeroGradient;";
    writeFoamFile(dir, "0/alpha.powder", "volScalarField",
                  "dimensions [0 0 0 0 0 0 0];\n\ninternalField uniform 0;\n\n" +
                      boundary(s, zg, "type fixedValue; value uniform 1;",
                               "type inletOutlet; inletValue uniform 0; value uniform 0;", zg, zg,
                               zg));
    // Paddles: MRF imposes the frame's velocity on wall faces of zone cells; the few paddle faces
    // of cells left out of the zone (next to the bore) turn with rotatingWallVelocity, which drops
    // the normal component, so no flux crosses them. The sliding mesh moves the paddles and the
    // shaft inside the zone, and movingWallVelocity follows that motion; the shaft's stubs in the
    // stationary end layers turn in place (rotatingWallVelocity).
    const bool sm = s.method == "sm";
    const std::string moving = "type movingWallVelocity; value uniform (0 0 0);";
    writeFoamFile(dir, "0/U", "volVectorField",
                  "dimensions [0 1 -1 0 0 0 0];\n\ninternalField uniform (0 0 0);\n\n" +
                      boundary(s, "type noSlip;",
                               "type flowRateInletVelocity; volumetricFlowRate constant " +
                                   num(s.feedM3S()) + "; value uniform (0 0 0);",
                               "type pressureInletOutletVelocity; value uniform (0 0 0);",
                               sm ? moving : rotatingWall(s), sm ? moving : rotatingWall(s),
                               rotatingWall(s)));
    const std::string ffp = "type fixedFluxPressure; value uniform 0;";
    // prghTotalPressure fixes p itself (not p_rgh) at the discharge: powder leaving at the bottom
    // of the outlet sees ambient pressure, not a column of its own weight.
    writeFoamFile(dir, "0/p_rgh", "volScalarField",
                  "dimensions [1 -1 -2 0 0 0 0];\n\ninternalField uniform 0;\n\n" +
                      boundary(s, ffp, ffp,
                               "type prghTotalPressure; p0 uniform 0; value uniform 0;", ffp, ffp,
                               ffp));
}

}  // namespace

double initialBedHeight(const scene::MixerScene& s) {
    const auto& g = s.geometry;
    return scene::depositHeight(s.initialLoadingKg / s.bulkDensity(), g.radius(), g.length);
}

void writeMixerMeshCase(const scene::MixerScene& s, const fs::path& dir, int np) {
    const auto& g = s.geometry;
    fs::create_directories(dir / "constant" / "triSurface");
    barrelSurface(g).write(dir / "constant/triSurface/barrel.stl");
    shaftSurface(g).write(dir / "constant/triSurface/shaft.stl");
    paddleSurface(g).write(dir / "constant/triSurface/paddles.stl");
    if (onOGrid(s)) {
        writeFoamFile(dir, "system/blockMeshDict", "dictionary", ogridBlockMeshDict(s));
        writeFoamFile(dir, "system/topoSetDict", "dictionary", ogridTopoSetDict(s));
        writeFoamFile(dir, "system/topoSetDict.inlet", "dictionary", ogridInletTopoSetDict(s));
        writeFoamFile(dir, "system/createPatchDict", "dictionary", ogridCreatePatchDict());
    } else {
        writeFoamFile(dir, "system/blockMeshDict", "dictionary", blockMeshDict(s));
        writeFoamFile(dir, "system/snappyHexMeshDict", "dictionary", snappyHexMeshDict(s));
        writeFoamFile(dir, "system/topoSetDict", "dictionary", topoSetDict(s));
    }
    writeMixerControlDict(s, dir, false, false);
    writeFoamFile(dir, "system/fvSchemes", "dictionary", fvSchemes(s));
    writeFoamFile(dir, "system/fvSolution", "dictionary", fvSolution(s));
    writeFoamFile(dir, "system/decomposeParDict", "dictionary", decomposeParDict(np));
}

void writeMixerControlDict(const scene::MixerScene& s, const fs::path& dir, bool keepAllTimes,
                           bool profile, double timeOffset) {
    writeFoamFile(dir, "system/controlDict", "dictionary", controlDict(s, keepAllTimes, profile, timeOffset));
}

std::vector<std::vector<std::string>> mixerMeshSteps(const scene::MixerScene& s) {
    if (onOGrid(s)) return ogridMeshSteps();
    return {{"blockMesh"}, {"snappyHexMesh", "-overwrite"}, {"topoSet", "-constant"},
            {"checkMesh", "-constant"}};
}

void writeMixerSolverCase(const scene::MixerScene& s, const fs::path& dir) {
    const auto& g = s.geometry;
    writeFoamFile(dir, "constant/transportProperties", "dictionary", transportProperties(s));
    writeFoamFile(dir, "constant/g", "uniformDimensionedVectorField",
                  "dimensions [0 1 -2 0 0 0 0];\nvalue (0 0 " + num(-s.gravity) + ");\n");
    // p is gauge with 0 at the top of the bore: the granular pressure needs no other reference.
    writeFoamFile(dir, "constant/hRef", "uniformDimensionedScalarField",
                  "dimensions [0 1 0 0 0 0 0];\nvalue " + num(g.radius()) + ";\n");
    writeFoamFile(dir, "constant/turbulenceProperties", "dictionary", "simulationType laminar;\n");
    writeFoamFile(dir, "constant/dynamicMeshDict", "dictionary", dynamicMeshDict(s));
    if (s.method != "sm")
        writeFoamFile(dir, "constant/MRFProperties", "dictionary", mrfProperties(s));
    writeFields(s, dir);
    const double zb = initialBedHeight(s);
    writeFoamFile(dir, "system/setFieldsDict", "dictionary",
                  "defaultFieldValues ( volScalarFieldValue alpha.powder 0 );\n\nregions\n(\n"
                  "    boxToCell\n    {\n        box " +
                      vec(-1, -1, -1) + ' ' + vec(g.length + 1, 1, zb) +
                      ";\n        fieldValues ( volScalarFieldValue alpha.powder 1 );\n    }\n);\n");
}

}  // namespace mixload::cases
