// SPDX-License-Identifier: GPL-3.0-or-later
#include "schaeffer.H"
#include "addToRunTimeSelectionTable.H"

namespace Foam
{
namespace viscosityModels
{
    defineTypeNameAndDebug(schaeffer, 0);
    addToRunTimeSelectionTable(viscosityModel, schaeffer, dictionary);
}
}


Foam::viscosityModels::schaeffer::schaeffer
(
    const word& name,
    const dictionary& viscosityProperties,
    const volVectorField& U,
    const surfaceScalarField& phi
)
:
    granularViscosityModel(typeName, name, viscosityProperties, U, phi),
    muConst_(0)
{
    readCommon();
    readModel();
    correct();
}


void Foam::viscosityModels::schaeffer::readModel()
{
    muConst_ = readPositive("mu");
}
