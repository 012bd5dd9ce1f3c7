// SPDX-License-Identifier: GPL-3.0-or-later
#include "collapseMonitor.H"
#include "addToRunTimeSelectionTable.H"
#include "volFields.H"
#include "OSspecific.H"

namespace Foam
{
namespace functionObjects
{
    defineTypeNameAndDebug(collapseMonitor, 0);
    addToRunTimeSelectionTable(functionObject, collapseMonitor, dictionary);
}
}


Foam::functionObjects::collapseMonitor::collapseMonitor
(
    const word& name,
    const Time& runTime,
    const dictionary& dict
)
:
    fvMeshFunctionObject(name, runTime, dict),
    peakKE_(0),
    restSince_(-1),
    atRest_(false)
{
    read(dict);
    peakKE_ = getProperty<scalar>("peakKE", 0);
    restSince_ = getProperty<scalar>("restSince", -1);

    if (Pstream::master())
    {
        const fileName dir =
            time_.globalPath()/"postProcessing"/name/time_.timeName();
        mkDir(dir);
        history_.reset(new OFstream(dir/"collapse.dat"));
        history_() << "# time powderVolume kineticEnergy front height" << nl;
    }
}


bool Foam::functionObjects::collapseMonitor::read(const dictionary& dict)
{
    fvMeshFunctionObject::read(dict);
    alphaName_ = dict.get<word>("alpha");
    rho_ = dict.get<scalar>("rho");
    x0_ = dict.get<scalar>("x0");
    binWidth_ = dict.get<scalar>("binWidth");
    nBins_ = dict.get<label>("nBins");
    hMin_ = dict.get<scalar>("hMin");
    restFraction_ = dict.get<scalar>("restFraction");
    restTime_ = dict.get<scalar>("restTime");
    minTime_ = dict.get<scalar>("minTime");
    return true;
}


Foam::scalarField Foam::functionObjects::collapseMonitor::profile() const
{
    const volScalarField& alpha = lookupObject<volScalarField>(alphaName_);
    const scalar depth = mesh_.bounds().span().z();
    const vectorField& C = mesh_.C().primitiveField();
    const scalarField& V = mesh_.V();

    scalarField h(nBins_, Zero);
    forAll(C, celli)
    {
        const label b = label((C[celli].x() - x0_)/binWidth_);
        if (b >= 0 && b < nBins_)
        {
            h[b] += alpha[celli]*V[celli];
        }
    }
    Pstream::listCombineGather(h, plusEqOp<scalar>());
    Pstream::listCombineScatter(h);
    h /= binWidth_*depth;
    return h;
}


Foam::scalar Foam::functionObjects::collapseMonitor::front
(
    const scalarField& h
) const
{
    label last = -1;
    forAll(h, i)
    {
        if (h[i] >= hMin_)
        {
            last = i;
        }
    }
    if (last < 0)
    {
        return x0_;
    }
    // Right edge of the last bin holding at least hMin, plus the filled share of the next one:
    // exact for the initial step profile and continuous as a thin front advances.
    const scalar edge = x0_ + (last + 1)*binWidth_;
    if (last + 1 >= h.size())
    {
        return edge;
    }
    return edge + min(h[last + 1]/hMin_, scalar(1))*binWidth_;
}


void Foam::functionObjects::collapseMonitor::writeProfile
(
    const scalarField& h
) const
{
    if (!Pstream::master())
    {
        return;
    }
    const fileName dir = time_.globalPath()/"postProcessing"/name()/"profiles";
    mkDir(dir);
    // Written under a temporary name and renamed: a reader never sees half a profile.
    const fileName tmp = dir/(time_.timeName() + ".tmp");
    {
        OFstream os(tmp);
        os << "# x height" << nl;
        forAll(h, i)
        {
            os << x0_ + (i + 0.5)*binWidth_ << ' ' << h[i] << nl;
        }
    }
    mv(tmp, dir/(time_.timeName() + ".dat"));
}


bool Foam::functionObjects::collapseMonitor::execute()
{
    const volScalarField& alpha = lookupObject<volScalarField>(alphaName_);
    const volVectorField& U = lookupObject<volVectorField>("U");
    const scalarField& V = mesh_.V();

    const scalar volume = gSum(alpha.primitiveField()*V);
    const scalar ke =
        0.5*rho_*gSum(alpha.primitiveField()*magSqr(U.primitiveField())*V);
    const scalarField h(profile());
    const scalar L = front(h);
    const scalar H = max(h);

    if (history_.valid())
    {
        history_()
            << time_.value() << ' ' << volume << ' ' << ke << ' '
            << L << ' ' << H << endl;
    }

    peakKE_ = max(peakKE_, ke);
    const scalar t = time_.value();
    if (t >= minTime_ && peakKE_ > 0 && ke < restFraction_*peakKE_)
    {
        if (restSince_ < 0)
        {
            restSince_ = t;
        }
        if (!atRest_ && t - restSince_ >= restTime_)
        {
            atRest_ = true;
            Info<< type() << ' ' << name() << ": powder at rest at t = " << t
                << " (kinetic energy " << ke << " < " << restFraction_
                << " x peak " << peakKE_ << " since t = " << restSince_
                << ")" << endl;
            if (Pstream::master())
            {
                OFstream os
                (
                    time_.globalPath()/"postProcessing"/name()/"rest"
                );
                os << t << nl;
            }
            writeProfile(h);
            const_cast<Time&>(time_).writeAndEnd();
        }
    }
    else
    {
        restSince_ = -1;
    }
    setProperty("peakKE", peakKE_);
    setProperty("restSince", restSince_);
    return true;
}


bool Foam::functionObjects::collapseMonitor::write()
{
    writeProfile(profile());
    return true;
}


bool Foam::functionObjects::collapseMonitor::end()
{
    writeProfile(profile());
    return true;
}
