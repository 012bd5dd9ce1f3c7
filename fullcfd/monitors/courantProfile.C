// SPDX-License-Identifier: GPL-3.0-or-later
#include "courantProfile.H"
#include "addToRunTimeSelectionTable.H"
#include "volFields.H"
#include "surfaceFields.H"
#include "fvcSurfaceIntegrate.H"
#include "fvc.H"
#include "OSspecific.H"

namespace Foam
{
namespace functionObjects
{
    defineTypeNameAndDebug(courantProfile, 0);
    addToRunTimeSelectionTable(functionObject, courantProfile, dictionary);
}
}

namespace
{
// One rank's candidate for the largest Courant number, reduced by value.
struct Peak
{
    Foam::scalar co = -1, alpha = 0, speed = 0;
    Foam::vector at = Foam::vector::zero;
    Foam::label region = -1;
};

void reducePeak(Peak& p)
{
    using namespace Foam;
    const scalar best = returnReduce(p.co, maxOp<scalar>());
    // Only the rank holding the maximum keeps its values; the others send zeros, so sums pick it.
    const bool mine = p.co == best;
    label owner = mine ? Pstream::myProcNo() : Pstream::nProcs();
    reduce(owner, minOp<label>());
    const bool keep = owner == Pstream::myProcNo();
    scalar alpha = keep ? p.alpha : 0, speed = keep ? p.speed : 0;
    vector at = keep ? p.at : vector::zero;
    label region = keep ? p.region : 0;
    reduce(alpha, sumOp<scalar>());
    reduce(speed, sumOp<scalar>());
    reduce(at, sumOp<vector>());
    reduce(region, sumOp<label>());
    p.co = best;
    p.alpha = alpha;
    p.speed = speed;
    p.at = at;
    p.region = region;
}
}


Foam::functionObjects::courantProfile::courantProfile
(
    const word& name,
    const Time& runTime,
    const dictionary& dict
)
:
    fvMeshFunctionObject(name, runTime, dict),
    zone_(-1),
    zoneX0_(GREAT),
    zoneX1_(-GREAT)
{
    read(dict);
    if (Pstream::master())
    {
        const fileName dir =
            time_.globalPath()/"postProcessing"/name/time_.timeName();
        mkDir(dir);
        out_.reset(new OFstream(dir/"courant.dat"));
        out_()
            << "# time deltaT co_mean co_max co_x co_y co_z co_alpha co_speed co_region"
            << " aco_max aco_x aco_y aco_z aco_alpha aco_speed aco_region"
            << "  (region: 0 rotor zone, 1 end layer, 2 ring outside the zone)" << nl;
        out_().precision(8);
    }
}


bool Foam::functionObjects::courantProfile::read(const dictionary& dict)
{
    fvMeshFunctionObject::read(dict);
    alphaName_ = dict.get<word>("alpha");
    zone_ = mesh_.cellZones().findZoneID(dict.getOrDefault<word>("zone", word::null));
    if (zone_ >= 0)
    {
        const labelList& cells = mesh_.cellZones()[zone_];
        forAll(cells, i)
        {
            zoneX0_ = min(zoneX0_, mesh_.C()[cells[i]].x());
            zoneX1_ = max(zoneX1_, mesh_.C()[cells[i]].x());
        }
        reduce(zoneX0_, minOp<scalar>());
        reduce(zoneX1_, maxOp<scalar>());
    }
    return true;
}


Foam::label Foam::functionObjects::courantProfile::region(label celli) const
{
    if (zone_ < 0) return 2;
    if (mesh_.cellZones()[zone_].whichCell(celli) >= 0) return 0;
    const scalar x = mesh_.C()[celli].x();
    return (x < zoneX0_ || x > zoneX1_) ? 1 : 2;
}


bool Foam::functionObjects::courantProfile::execute()
{
    const surfaceScalarField& phi = lookupObject<surfaceScalarField>("phi");
    const volScalarField& alpha = lookupObject<volScalarField>(alphaName_);
    const volVectorField& U = lookupObject<volVectorField>("U");
    const scalar dt = time_.deltaTValue();
    const scalarField co
    (
        0.5*fvc::surfaceSum(mag(phi))().primitiveField()/mesh_.V().field()*dt
    );

    Peak flow, iface;
    forAll(co, i)
    {
        const scalar a = alpha[i];
        const bool near = a >= 0.01 && a <= 0.99;
        if (co[i] > flow.co)
        {
            flow.co = co[i];
            flow.alpha = a;
            flow.speed = mag(U[i]);
            flow.at = mesh_.C()[i];
            flow.region = i;
        }
        if (near && co[i] > iface.co)
        {
            iface.co = co[i];
            iface.alpha = a;
            iface.speed = mag(U[i]);
            iface.at = mesh_.C()[i];
            iface.region = i;
        }
    }
    if (flow.region >= 0) flow.region = region(flow.region);
    if (iface.region >= 0) iface.region = region(iface.region);
    else iface.co = 0;
    const scalar coMean =
        returnReduce(sum(co*mesh_.V().field()), sumOp<scalar>())/gSum(mesh_.V().field());
    reducePeak(flow);
    reducePeak(iface);

    if (out_.valid())
    {
        out_()
            << time_.value() << ' ' << dt << ' ' << coMean << ' ' << flow.co << ' '
            << flow.at.x() << ' ' << flow.at.y() << ' ' << flow.at.z() << ' '
            << flow.alpha << ' ' << flow.speed << ' ' << flow.region << ' '
            << iface.co << ' ' << iface.at.x() << ' ' << iface.at.y() << ' ' << iface.at.z()
            << ' ' << iface.alpha << ' ' << iface.speed << ' ' << iface.region << nl;
    }
    return true;
}


bool Foam::functionObjects::courantProfile::write()
{
    if (out_.valid()) out_().flush();
    return true;
}
