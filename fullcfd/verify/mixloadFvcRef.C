/*---------------------------------------------------------------------------*\
  mixloadFvcRef: OpenFOAM's own finite-volume operators on a case's written fields, written in
  binary (full double precision) next to them, as the reference that mixload's reduced-model
  operators (rom/fv_operators) are verified against. Part of mixload, GPL-3.0-or-later.

  For each selected time it reads alpha.powder, U and phi with their boundary conditions and writes
    fvcRef.interpolate.alpha   fvc::interpolate(alpha)            (the case's interpolation scheme)
    fvcRef.weights             mesh.weights()                     (linear interpolation weights)
    fvcRef.grad.alpha          fvc::grad(alpha)                   (gradSchemes)
    fvcRef.div.phi             fvc::div(phi)
    fvcRef.laplacian.alpha     fvc::laplacian(alpha)              (laplacianSchemes)
    fvcRef.strainRate          sqrt(2) |symm(fvc::grad(U))|       (the mu(I) shear rate)
    fvcRef.reconstruct.phi     fvc::reconstruct(phi)              (cell velocities from the face flux)
    fvcRef.laplacianP.alpha    fvc::laplacian(interpolate(p), alpha)  (a face diffusivity)
    fvcRef.nu.powder           the powder's viscosity model (transportProperties, with p) evaluated
\*---------------------------------------------------------------------------*/

#include "fvCFD.H"
#include "viscosityModel.H"

template<class FieldType>
void writeBinary(const FieldType& f)
{
    f.writeObject(IOstream::BINARY, IOstream::currentVersion, IOstream::UNCOMPRESSED, true);
}

int main(int argc, char *argv[])
{
    timeSelector::addOptions();
    #include "setRootCase.H"
    #include "createTime.H"
    instantList timeDirs = timeSelector::select0(runTime, args);
    #include "createMesh.H"

    forAll(timeDirs, timeI)
    {
        runTime.setTime(timeDirs[timeI], timeI);
        Info<< "Time = " << runTime.timeName() << endl;
        mesh.readUpdate();

        volScalarField alpha
        (
            IOobject("alpha.powder", runTime.timeName(), mesh, IOobject::MUST_READ, IOobject::NO_WRITE),
            mesh
        );
        volVectorField U
        (
            IOobject("U", runTime.timeName(), mesh, IOobject::MUST_READ, IOobject::NO_WRITE),
            mesh
        );
        surfaceScalarField phi
        (
            IOobject("phi", runTime.timeName(), mesh, IOobject::MUST_READ, IOobject::NO_WRITE),
            mesh
        );

        surfaceScalarField alphaf("fvcRef.interpolate.alpha", fvc::interpolate(alpha));
        writeBinary(alphaf);
        surfaceScalarField w
        (
            IOobject("fvcRef.weights", runTime.timeName(), mesh, IOobject::NO_READ, IOobject::NO_WRITE),
            mesh.weights()
        );
        writeBinary(w);
        volVectorField gradAlpha("fvcRef.grad.alpha", fvc::grad(alpha));
        writeBinary(gradAlpha);
        volScalarField divPhi("fvcRef.div.phi", fvc::div(phi));
        writeBinary(divPhi);
        volScalarField lapAlpha("fvcRef.laplacian.alpha", fvc::laplacian(alpha));
        writeBinary(lapAlpha);
        volScalarField strainRate("fvcRef.strainRate", Foam::sqrt(scalar(2))*mag(symm(fvc::grad(U))));
        writeBinary(strainRate);

        // The powder's viscosity model as the solver builds it; it finds p in the registry.
        volScalarField p
        (
            IOobject("p", runTime.timeName(), mesh, IOobject::MUST_READ, IOobject::NO_WRITE),
            mesh
        );
        IOdictionary transport
        (
            IOobject("transportProperties", runTime.constant(), mesh, IOobject::MUST_READ, IOobject::NO_WRITE, false)
        );
        autoPtr<viscosityModel> powder
        (
            viscosityModel::New("fvcRef.nuModel", transport.subDict("powder"), U, phi)
        );
        volVectorField rec("fvcRef.reconstruct.phi", fvc::reconstruct(phi));
        writeBinary(rec);
        volScalarField lapP("fvcRef.laplacianP.alpha", fvc::laplacian(fvc::interpolate(p), alpha));
        writeBinary(lapP);

        powder->correct();
        volScalarField nuPowder("fvcRef.nu.powder", powder->nu());
        writeBinary(nuPowder);
    }
    Info<< "End" << endl;
    return 0;
}
