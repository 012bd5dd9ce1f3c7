// SPDX-License-Identifier: GPL-3.0-or-later
// mixload's interFoam: OpenFOAM v1912's interFoam time loop, built from the stock pieces of
// Debian's source package (createFields.H, alphaEqnSubCycle.H, UEqn.H, pEqn.H, ...), with two
// additions that leave the stock behaviour unchanged unless a case asks for them:
//  - profiling scopes around each stage of a step (alpha transport, the viscosity update, the
//    momentum predictor, the pressure correctors, the mesh update), so that the case's
//    `profiling { active true; }` reports where a step's time goes, not only the linear solves;
//  - PIMPLE `courantAlphaMin`: the flow and interface Courant numbers that set the time step are
//    taken over cells holding at least this powder fraction (0, the default: every cell, as stock).
//    In the mixer the time step was set by air moving at five times the paddle-tip speed in thin
//    end layers (README, "Cost of a steady point"); the powder carries the answer;
//  - PIMPLE `fragmentAMI`: the sliding mesh's AMI pairs carry one flux per overlap fragment, in
//    the pressure and powder equations and in the time step (fragmentAMI.H), so that powder is
//    conserved across a non-conformal interface; pEqn.H, correctPhi.H and alphaEqn.H here are
//    v1912's with that switch added.
// Everything else (schemes, MULES, PIMPLE, MRF, mesh motion) is the stock solver's.

#include "fvCFD.H"
#include "dynamicFvMesh.H"
#include "CMULES.H"
#include "EulerDdtScheme.H"
#include "localEulerDdtScheme.H"
#include "CrankNicolsonDdtScheme.H"
#include "subCycle.H"
#include "immiscibleIncompressibleTwoPhaseMixture.H"
#include "turbulentTransportModel.H"
#include "pimpleControl.H"
#include "fvOptions.H"
#include "CorrectPhi.H"
#include "fvcSmooth.H"
#include "profiling.H"
#include "fragmentAMI.H"

int main(int argc, char *argv[])
{
    argList::addNote
    (
        "interFoam (OpenFOAM v1912) with stage profiling and an optional powder-only Courant"
        " limit, for mixload."
    );

    #include "postProcess.H"

    #include "addCheckCaseOptions.H"
    #include "setRootCaseLists.H"
    #include "createTime.H"
    #include "createDynamicFvMesh.H"
    #include "initContinuityErrs.H"
    #include "createDyMControls.H"
    #include "createFields.H"
    #include "createAlphaFluxes.H"
    #include "initCorrectPhi.H"
    #include "createUfIfPresent.H"

    turbulence->validate();

    Foam::fragmentAMI::Coupling fragments(mesh, pimple.dict(), correctPhi);

    if (!LTS)
    {
        #include "powderCourantNo.H"
        #include "setInitialDeltaT.H"
    }

    Info<< "\nStarting time loop\n" << endl;

    while (runTime.run())
    {
        #include "readDyMControls.H"

        if (LTS)
        {
            #include "setRDeltaT.H"
        }
        else
        {
            #include "powderCourantNo.H"
            if (fragments.active())
            {
                const scalar fragmentCo = fragments.courant
                (
                    phi, runTime.deltaTValue(), alpha1, courantAlphaMin
                );
                Info<< "Fragment Courant Number (next to the AMI pairs) max: " << fragmentCo
                    << endl;
                CoNum = max(CoNum, fragmentCo);
                alphaCoNum = max(alphaCoNum, fragmentCo);
            }
            #include "setDeltaT.H"
        }

        ++runTime;

        Info<< "Time = " << runTime.timeName() << nl << endl;

        while (pimple.loop())
        {
            if (pimple.firstIter() || moveMeshOuterCorrectors)
            {
                addProfiling(meshUpdate, "mixload::meshUpdate");
                mesh.update();

                if (mesh.changing())
                {
                    if (mesh.topoChanging())
                    {
                        talphaPhi1Corr0.clear();
                    }

                    gh = (g & mesh.C()) - ghRef;
                    ghf = (g & mesh.Cf()) - ghRef;

                    MRF.update();

                    if (correctPhi)
                    {
                        phi = mesh.Sf() & Uf();

                        #include "correctPhi.H"

                        fvc::makeRelative(phi, U);

                        mixture.correct();
                    }

                    if (checkMeshCourantNo)
                    {
                        #include "meshCourantNo.H"
                    }
                }
            }

            {
                addProfiling(alpha, "mixload::alpha");
                #include "alphaControls.H"
                #include "alphaEqnSubCycle.H"
            }

            {
                addProfiling(viscosity, "mixload::viscosity");
                mixture.correct();
            }

            if (pimple.frozenFlow())
            {
                continue;
            }

            // UEqn must outlive the predictor: the pressure correctors use its diagonal.
            addProfiling(momentum, "mixload::momentum");
            #include "UEqn.H"
            endProfiling(momentum);

            while (pimple.correct())
            {
                addProfiling(pressure, "mixload::pressure");
                #include "pEqn.H"
            }

            if (pimple.turbCorr())
            {
                turbulence->correct();
            }
        }

        runTime.write();

        runTime.printExecutionTime(Info);
    }

    Info<< "End\n" << endl;

    return 0;
}
