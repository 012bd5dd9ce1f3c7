// SPDX-License-Identifier: GPL-3.0-or-later
#include "cases/collapse2d.hpp"

#include <algorithm>
#include <sstream>

#include "cases/foam_dict.hpp"
#include "cases/foam_numerics.hpp"

namespace mixload::cases {

double columnOverlap(double x0, double x1, double y0, double y1, double Li, double Hi) {
    const double ox = std::max(0.0, std::min(x1, Li) - std::max(x0, 0.0));
    const double oy = std::max(0.0, std::min(y1, Hi) - std::max(y0, 0.0));
    return ox * oy / ((x1 - x0) * (y1 - y0));
}

namespace {

std::string blockMeshDict(const scene::CollapseScene& s) {
    const double W = s.domainWidth(), H = s.domainHeight(), D = s.dx();
    std::ostringstream os;
    os << "convertToMeters 1;\n\nvertices\n(\n"
       << "    (0 0 0) (" << num(W) << " 0 0) (" << num(W) << " " << num(H) << " 0) (0 " << num(H)
       << " 0)\n"
       << "    (0 0 " << num(D) << ") (" << num(W) << " 0 " << num(D) << ") (" << num(W) << " "
       << num(H) << " " << num(D) << ") (0 " << num(H) << " " << num(D) << ")\n);\n\n"
       << "blocks\n(\n    hex (0 1 2 3 4 5 6 7) (" << s.nx() << " " << s.ny()
       << " 1) simpleGrading (1 1 1)\n);\n\nedges ();\n\nboundary\n(\n"
       << "    leftWall { type wall; faces ((0 4 7 3)); }\n"
       << "    bottom { type wall; faces ((0 1 5 4)); }\n"
       << "    atmosphere { type patch; faces ((1 2 6 5) (3 7 6 2)); }\n"
       << "    frontAndBack { type empty; faces ((0 3 2 1) (4 5 6 7)); }\n);\n";
    return os.str();
}

std::string alphaField(const scene::CollapseScene& s) {
    const int nx = s.nx(), ny = s.ny();
    const double dx = s.dx();
    std::ostringstream os;
    os.precision(10);
    os << "dimensions [0 0 0 0 0 0 0];\n\ninternalField nonuniform List<scalar>\n"
       << static_cast<long>(nx) * ny << "\n(\n";
    // blockMesh numbers the cells of one block x fastest, then y.
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i)
            os << columnOverlap(i * dx, (i + 1) * dx, j * dx, (j + 1) * dx, s.length, s.height())
               << '\n';
    os << ");\n\nboundaryField\n{\n"
       << "    leftWall { type zeroGradient; }\n"
       << "    bottom { type zeroGradient; }\n"
       << "    atmosphere { type inletOutlet; inletValue uniform 0; value uniform 0; }\n"
       << "    frontAndBack { type empty; }\n}\n";
    return os.str();
}

const char* kU =
    "dimensions [0 1 -1 0 0 0 0];\n\ninternalField uniform (0 0 0);\n\nboundaryField\n{\n"
    "    leftWall { type slip; }\n"
    "    bottom { type noSlip; }\n"
    "    atmosphere { type pressureInletOutletVelocity; value uniform (0 0 0); }\n"
    "    frontAndBack { type empty; }\n}\n";

const char* kPrgh =
    "dimensions [1 -1 -2 0 0 0 0];\n\ninternalField uniform 0;\n\nboundaryField\n{\n"
    "    leftWall { type fixedFluxPressure; value uniform 0; }\n"
    "    bottom { type fixedFluxPressure; value uniform 0; }\n"
    "    atmosphere { type totalPressure; p0 uniform 0; }\n"
    "    frontAndBack { type empty; }\n}\n";

std::string controlDict(const scene::CollapseScene& s, const std::string& libs) {
    const double tStar = s.tStar();
    const int nBins = s.nx();
    std::ostringstream os;
    os << "application interFoam;\nlibs (" << libs << ");\n"
       << "startFrom latestTime;\nstartTime 0;\nstopAt endTime;\n"
       << "endTime " << num(s.capTstar * tStar) << ";  // cap only: the monitor ends the run at rest\n"
       << "deltaT " << num(1e-3 * tStar) << ";\n"
       << "writeControl adjustable;\nwriteInterval " << num(tStar / s.writesPerTstar) << ";\n"
       << "purgeWrite 0;\nwriteFormat ascii;\nwritePrecision 8;\nwriteCompression off;\n"
       << "timeFormat general;\ntimePrecision 8;\nrunTimeModifiable yes;\n"
       << "adjustTimeStep yes;\nmaxCo " << num(s.maxCourant) << ";\nmaxAlphaCo "
       << num(s.maxCourant) << ";\nmaxDeltaT " << num(0.01 * tStar)
       << ";\n\nfunctions\n{\n    " << kCollapseMonitor << "\n    {\n"
       << "        type collapseMonitor;\n"
       << "        alpha alpha.powder;\n"
       << "        rho " << num(s.material.bulkDensity()) << ";\n"
       << "        x0 0;\n        binWidth " << num(s.dx()) << ";\n        nBins " << nBins << ";\n"
       << "        hMin " << num(0.5 * s.dx()) << ";  // front: where less than half a cell of powder remains\n"
       << "        restFraction " << num(s.restFraction) << ";\n"
       << "        restTime " << num(s.restTimeTstar * tStar) << ";\n"
       << "        minTime " << num(1.0 * tStar) << ";\n"
       << "        writeControl writeTime;\n    }\n}\n";
    return os.str();
}

std::string transportProperties(const scene::CollapseScene& s) {
    const auto& m = s.material;
    return cases::transportProperties({s.rheology, s.material.bulkDensity(), s.muSCase(), s.muDCase(), m.I0,
                                        m.grainDiameter, m.grainDensity, s.etaMaxValue(), s.pMin});
}

}  // namespace

void writeCollapseCase(const scene::CollapseScene& s, const std::filesystem::path& dir, int np) {
    writeFoamFile(dir, "system/blockMeshDict", "dictionary", blockMeshDict(s));
    writeFoamFile(dir, "system/controlDict", "dictionary",
                  controlDict(s, mixloadFoamLibs()));
    writeFoamFile(dir, "system/fvSchemes", "dictionary", interFoamSchemes());
    writeFoamFile(dir, "system/fvSolution", "dictionary", interFoamSolution("alpha.powder"));
    writeFoamFile(dir, "system/decomposeParDict", "dictionary", decomposeParDict(np));
    writeFoamFile(dir, "constant/transportProperties", "dictionary", transportProperties(s));
    writeFoamFile(dir, "constant/g", "uniformDimensionedVectorField",
                  "dimensions [0 1 -2 0 0 0 0];\nvalue (0 " + num(-s.gravity) + " 0);\n");
    // p is then gauge at the top of the domain: the granular pressure needs no other reference.
    writeFoamFile(dir, "constant/hRef", "uniformDimensionedScalarField",
                  "dimensions [0 1 0 0 0 0 0];\nvalue " + num(s.domainHeight()) + ";\n");
    writeFoamFile(dir, "constant/turbulenceProperties", "dictionary", "simulationType laminar;\n");
    writeFoamFile(dir, "0/U", "volVectorField", kU);
    writeFoamFile(dir, "0/p_rgh", "volScalarField", kPrgh);
    writeFoamFile(dir, "0/alpha.powder", "volScalarField", alphaField(s));
}

}  // namespace mixload::cases
