// SPDX-License-Identifier: GPL-3.0-or-later
#include "muI.H"
#include "addToRunTimeSelectionTable.H"

namespace Foam
{
namespace viscosityModels
{
    defineTypeNameAndDebug(muI, 0);
    addToRunTimeSelectionTable(viscosityModel, muI, dictionary);
}
}


Foam::viscosityModels::muI::muI
(
    const word& modelType,
    const word& name,
    const dictionary& viscosityProperties,
    const volVectorField& U,
    const surfaceScalarField& phi
)
:
    granularViscosityModel(modelType, name, viscosityProperties, U, phi),
    law_{0, 0, 0},
    d_(0),
    rhoS_(0)
{
    readCommon();
    readMuI();
}


Foam::viscosityModels::muI::muI
(
    const word& name,
    const dictionary& viscosityProperties,
    const volVectorField& U,
    const surfaceScalarField& phi
)
:
    muI(typeName, name, viscosityProperties, U, phi)
{
    correct();
}


void Foam::viscosityModels::muI::readMuI()
{
    law_.muS = readPositive("muS");
    law_.muD = readPositive("muD");
    law_.I0 = readPositive("I0");
    d_ = readPositive("d");
    rhoS_ = readPositive("rhoS");
    if (!(law_.muD > law_.muS))
    {
        FatalIOErrorInFunction(coeffs_)
            << "coefficient muD = " << law_.muD
            << " is out of range: it must be > muS = " << law_.muS
            << exit(FatalIOError);
    }
}


void Foam::viscosityModels::muI::readModel()
{
    readMuI();
}
