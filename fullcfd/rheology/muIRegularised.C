// SPDX-License-Identifier: GPL-3.0-or-later
#include "muIRegularised.H"
#include "addToRunTimeSelectionTable.H"

namespace Foam
{
namespace viscosityModels
{
    defineTypeNameAndDebug(muIRegularised, 0);
    addToRunTimeSelectionTable(viscosityModel, muIRegularised, dictionary);
}
}


Foam::viscosityModels::muIRegularised::muIRegularised
(
    const word& name,
    const dictionary& viscosityProperties,
    const volVectorField& U,
    const surfaceScalarField& phi
)
:
    muI(typeName, name, viscosityProperties, U, phi)
{
    build();
    correct();
}


void Foam::viscosityModels::muIRegularised::build()
{
    reg_ = mixload::rheology::makeRegularisedLaw
    (
        law_,
        coeffs_.getOrDefault<scalar>("alpha", 1.9)
    );
    Info<< "muIRegularised: low-I branch below I_N = " << reg_.IN
        << " (A = " << reg_.A << ")" << endl;
    if (!reg_.wellPosed)
    {
        WarningInFunction
            << "mu(I) with muS = " << law_.muS << ", muD = " << law_.muD
            << ", I0 = " << law_.I0 << " has no well-posed window; the low-I"
            << " branch is joined at the least ill-posed I = " << reg_.IN
            << ". Expect mesh-dependent results." << endl;
    }
}


void Foam::viscosityModels::muIRegularised::readModel()
{
    readMuI();
    build();
}
