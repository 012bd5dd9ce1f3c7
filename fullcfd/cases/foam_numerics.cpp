// SPDX-License-Identifier: GPL-3.0-or-later
#include "cases/foam_numerics.hpp"

#include <cstdlib>
#include <sstream>

#include "cases/foam_dict.hpp"
#include "common/atomic_file.hpp"

namespace mixload::cases {

std::string rheologyLibraryPath() {
    if (const char* env = std::getenv("MIXLOAD_RHEOLOGY_LIB")) return env;
    return MIXLOAD_RHEOLOGY_LIB;
}

std::string monitorsLibraryPath() {
    if (const char* env = std::getenv("MIXLOAD_MONITORS_LIB")) return env;
    return MIXLOAD_MONITORS_LIB;
}

std::string mixloadFoamLibs() {
    return "\"" + rheologyLibraryPath() + "\" \"" + monitorsLibraryPath() + "\"";
}

bool refreshFoamLibs(const std::filesystem::path& caseDir) {
    const auto dict = caseDir / "system" / "controlDict";
    if (!std::filesystem::exists(dict)) return false;
    std::istringstream in(readFile(dict));
    std::ostringstream out;
    const std::string wanted = "libs (" + mixloadFoamLibs() + ");";
    bool changed = false;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("libs (", 0) == 0 && line != wanted) {
            line = wanted;
            changed = true;
        }
        out << line << '\n';
    }
    if (changed) writeFileAtomic(dict, out.str());
    return changed;
}

std::string interFoamSchemes() {
    // Bounded, mostly second-order schemes as in OpenFOAM's damBreak; the stress term
    // div(rho*nuEff*dev2(T(grad U))) is explicit and sees the large granular viscosity, which is
    // why the momentum predictor is on in interFoamSolution().
    return "ddtSchemes { default Euler; }\n"
           "gradSchemes { default Gauss linear; }\n"
           "divSchemes\n{\n"
           "    div(rhoPhi,U) Gauss linearUpwind grad(U);\n"
           "    div(phi,alpha) Gauss vanLeer;\n"
           "    div(phirb,alpha) Gauss linear;\n"
           "    div(((rho*nuEff)*dev2(T(grad(U))))) Gauss linear;\n}\n"
           "laplacianSchemes { default Gauss linear corrected; }\n"
           "interpolationSchemes { default linear; }\n"
           "snGradSchemes { default corrected; }\n";
}

std::string interFoamSolution(const std::string& alphaName) {
    return "solvers\n{\n"
           "    \"" + alphaName + ".*\"\n    {\n"
           "        nAlphaCorr 2; nAlphaSubCycles 1; cAlpha 1; MULESCorr yes; nLimiterIter 5;\n"
           "        solver smoothSolver; smoother symGaussSeidel; tolerance 1e-8; relTol 0;\n    }\n"
           "    \"pcorr.*\" { solver PCG; preconditioner DIC; tolerance 1e-5; relTol 0; }\n"
           "    p_rgh { solver PCG; preconditioner DIC; tolerance 1e-7; relTol 0.05; }\n"
           "    p_rghFinal { $p_rgh; relTol 0; }\n"
           "    \"U.*\" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-7; relTol 0; }\n"
           "}\n\n"
           "PIMPLE\n{\n    momentumPredictor yes;\n    nOuterCorrectors 1;\n    nCorrectors 3;\n"
           "    nNonOrthogonalCorrectors 0;\n}\n\n"
           "relaxationFactors { equations { \".*\" 1; } }\n";
}

std::string decomposeParDict(int np) {
    return "numberOfSubdomains " + std::to_string(np) +
           ";\nmethod simple;\ncoeffs { n (" + std::to_string(np) + " 1 1); }\n";
}

std::string transportProperties(const PowderTransport& t) {
    std::ostringstream os;
    os << "phases (powder air);\n\npowder\n{\n    transportModel " << t.rheology << ";\n"
       << "    rho " << num(t.bulkDensity) << ";\n    " << t.rheology << "Coeffs\n    {\n";
    if (t.rheology == "schaeffer") {
        os << "        mu " << num(t.muS) << ";  // constant friction: the material's mu_s\n";
    } else {
        os << "        muS " << num(t.muS) << ";\n        muD " << num(t.muD) << ";\n"
           << "        I0 " << num(t.I0) << ";\n        d " << num(t.grainDiameter) << ";\n"
           << "        rhoS " << num(t.grainDensity) << ";\n";
    }
    os << "        etaMax " << num(t.etaMax) << ";\n        pMin " << num(t.pMin) << ";\n"
       << "    }\n}\n\nair\n{\n    transportModel Newtonian;\n    nu " << num(t.airViscosity)
       << ";\n    rho 1.2;\n}\n\n"
       << "sigma 0;\n";
    return os.str();
}

}  // namespace mixload::cases
