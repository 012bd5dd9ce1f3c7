// SPDX-License-Identifier: GPL-3.0-or-later
#include "granularViscosityModel.H"
#include "muILaw.H"

Foam::viscosityModels::granularViscosityModel::granularViscosityModel
(
    const word& typeName,
    const word& name,
    const dictionary& viscosityProperties,
    const volVectorField& U,
    const surfaceScalarField& phi
)
:
    viscosityModel(name, viscosityProperties, U, phi),
    coeffs_(viscosityProperties.optionalSubDict(typeName + "Coeffs")),
    rho_(viscosityProperties.get<scalar>("rho")),
    etaMax_(0),
    pMin_(0),
    pName_("p"),
    nu_
    (
        IOobject
        (
            name,
            U_.time().timeName(),
            U_.db(),
            IOobject::NO_READ,
            IOobject::AUTO_WRITE
        ),
        U_.mesh(),
        dimensionedScalar(dimViscosity, Zero)
    )
{
    // Derived classes finish reading and call correct(): their coefficients are not yet constructed.
}


Foam::scalar Foam::viscosityModels::granularViscosityModel::readPositive
(
    const word& key
) const
{
    const scalar v = coeffs_.get<scalar>(key);
    if (!(v > 0))
    {
        FatalIOErrorInFunction(coeffs_)
            << "coefficient " << key << " = " << v
            << " is out of range: it must be > 0" << exit(FatalIOError);
    }
    return v;
}


void Foam::viscosityModels::granularViscosityModel::readCommon()
{
    if (!(rho_ > 0))
    {
        FatalIOErrorInFunction(viscosityProperties_)
            << "rho = " << rho_ << " is out of range: it must be > 0"
            << exit(FatalIOError);
    }
    etaMax_ = readPositive("etaMax");
    pMin_ = readPositive("pMin");
    pName_ = coeffs_.getOrDefault<word>("p", "p");
}


bool Foam::viscosityModels::granularViscosityModel::read
(
    const dictionary& viscosityProperties
)
{
    viscosityModel::read(viscosityProperties);
    coeffs_ = viscosityProperties.optionalSubDict(type() + "Coeffs");
    rho_ = viscosityProperties.get<scalar>("rho");
    readCommon();
    readModel();
    return true;
}


Foam::tmp<Foam::volScalarField>
Foam::viscosityModels::granularViscosityModel::calcNu() const
{
    using mixload::rheology::granularViscosity;

    tmp<volScalarField> tnu
    (
        new volScalarField
        (
            IOobject
            (
                "nuGranular",
                U_.time().timeName(),
                U_.mesh(),
                IOobject::NO_READ,
                IOobject::NO_WRITE,
                false
            ),
            U_.mesh(),
            dimensionedScalar("nuMax", dimViscosity, etaMax_/rho_)
        )
    );
    volScalarField& nu = tnu.ref();

    const volScalarField* pPtr = U_.db().findObject<volScalarField>(pName_);
    if (!pPtr)
    {
        return tnu;
    }
    const volScalarField& p = *pPtr;
    const tmp<volScalarField> tsr(strainRate());
    const volScalarField& sr = tsr();

    scalarField& nuI = nu.primitiveFieldRef();
    forAll(nuI, celli)
    {
        const scalar pc = max(p[celli], pMin_);
        nuI[celli] =
            granularViscosity(mu(sr[celli], pc), pc, sr[celli], etaMax_)/rho_;
    }

    volScalarField::Boundary& nuB = nu.boundaryFieldRef();
    forAll(nuB, patchi)
    {
        scalarField& nuP = nuB[patchi];
        const scalarField& pP = p.boundaryField()[patchi];
        const scalarField& srP = sr.boundaryField()[patchi];
        if (pP.size() != nuP.size())
        {
            continue;   // empty patches
        }
        forAll(nuP, facei)
        {
            const scalar pc = max(pP[facei], pMin_);
            nuP[facei] =
                granularViscosity(mu(srP[facei], pc), pc, srP[facei], etaMax_)
               /rho_;
        }
    }

    return tnu;
}
