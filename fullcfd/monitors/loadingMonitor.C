// SPDX-License-Identifier: GPL-3.0-or-later
#include "loadingMonitor.H"
#include "addToRunTimeSelectionTable.H"
#include "volFields.H"
#include "surfaceFields.H"
#include "OSspecific.H"
#include "steadyLoading.H"

namespace Foam
{
namespace functionObjects
{
    defineTypeNameAndDebug(loadingMonitor, 0);
    addToRunTimeSelectionTable(functionObject, loadingMonitor, dictionary);
}
}


Foam::functionObjects::loadingMonitor::loadingMonitor
(
    const word& name,
    const Time& runTime,
    const dictionary& dict
)
:
    fvMeshFunctionObject(name, runTime, dict),
    fed_(0),
    out_(0),
    steady_(false),
    zone_(-1)
{
    read(dict);
    fed_ = getProperty<scalar>("fed", 0);
    out_ = getProperty<scalar>("out", 0);
    ts_ = getProperty<scalarList>("sampleTimes", scalarList());
    ms_ = getProperty<scalarList>("sampleLoadings", scalarList());
    cs_ = getProperty<scalarList>("sampleOutflows", scalarList());

    if (Pstream::master())
    {
        const fileName dir =
            time_.globalPath()/"postProcessing"/name/time_.timeName();
        mkDir(dir);
        history_.reset(new OFstream(dir/"loading.dat"));
        history_()
            << "# time loading_kg inflow_kg_s outflow_kg_s fed_kg out_kg"
            << " max_powder_speed_m_s zone_loading_kg dense_loading_kg" << nl;
        history_().precision(12);
    }
}


Foam::labelList Foam::functionObjects::loadingMonitor::patchIDs
(
    const wordRes& names
) const
{
    const labelList ids(mesh_.boundaryMesh().patchSet(names).sortedToc());
    if (ids.empty())
    {
        FatalErrorInFunction
            << type() << ' ' << name() << ": no patch matches " << names
            << exit(FatalError);
    }
    return ids;
}


bool Foam::functionObjects::loadingMonitor::read(const dictionary& dict)
{
    fvMeshFunctionObject::read(dict);
    alphaName_ = dict.get<word>("alpha");
    rho_ = dict.get<scalar>("rho");
    inlets_ = patchIDs(dict.get<wordRes>("inletPatches"));
    outlets_ = patchIDs(dict.get<wordRes>("outletPatches"));
    feed_ = dict.get<scalar>("feed");
    window_ = dict.get<scalar>("window");
    period_ = dict.getOrDefault<scalar>("period", 0);
    residenceFraction_ = dict.getOrDefault<scalar>("residenceFraction", 0);
    tol_ = dict.get<scalar>("tolerance");
    flowTol_ = dict.get<scalar>("flowTolerance");
    minTime_ = dict.get<scalar>("minTime");
    maxPowderSpeed_ = dict.getOrDefault<scalar>("maxPowderSpeed", 0);
    pseudoTime_ = dict.get<bool>("pseudoTime");
    zone_ = mesh_.cellZones().findZoneID(dict.getOrDefault<word>("zone", word::null));
    return true;
}


Foam::scalar Foam::functionObjects::loadingMonitor::patchFlow
(
    const labelList& patches
) const
{
    // The MULES flux of the phase moved alpha this step; fall back to phi * alpha on a first step
    // of a solver that has not registered it.
    const word fluxName(IOobject::groupName("alphaPhi0", IOobject::group(alphaName_)));
    scalar q = 0;
    if (foundObject<surfaceScalarField>(fluxName))
    {
        const surfaceScalarField& f = lookupObject<surfaceScalarField>(fluxName);
        forAll(patches, i)
        {
            q += sum(f.boundaryField()[patches[i]]);
        }
    }
    else
    {
        const surfaceScalarField& phi = lookupObject<surfaceScalarField>("phi");
        const volScalarField& alpha = lookupObject<volScalarField>(alphaName_);
        forAll(patches, i)
        {
            q += sum(phi.boundaryField()[patches[i]]*alpha.boundaryField()[patches[i]]);
        }
    }
    reduce(q, sumOp<scalar>());
    return rho_*q;
}


bool Foam::functionObjects::loadingMonitor::execute()
{
    const volScalarField& alpha = lookupObject<volScalarField>(alphaName_);
    const scalar M = rho_*gSum(alpha.primitiveField()*mesh_.V());
    // Fastest powder cell (alpha > 0.5), absolute frame as interFoam stores U even under MRF.
    const volVectorField& U = lookupObject<volVectorField>("U");
    const scalar maxSpeed = gMax
    (
        pos(alpha.primitiveField() - 0.5)*mag(U.primitiveField())
    );
    // Powder in cells that are more than half powder: a layer thinner than about half a cell is
    // not resolved, and there the dense-flow law describes a smeared mixture, not a bed.
    const scalar Mdense =
        rho_*gSum(pos(alpha.primitiveField() - 0.5)*alpha.primitiveField()*mesh_.V());
    scalar Mzone = 0;
    if (zone_ >= 0)
    {
        const labelList& cells = mesh_.cellZones()[zone_];
        forAll(cells, i)
        {
            Mzone += alpha[cells[i]]*mesh_.V()[cells[i]];
        }
        Mzone = rho_*returnReduce(Mzone, sumOp<scalar>());
    }
    const scalar qIn = -patchFlow(inlets_);
    const scalar qOut = patchFlow(outlets_);
    const scalar dt = pseudoTime_ ? 1.0 : time_.deltaTValue();
    fed_ += qIn*dt;
    out_ += qOut*dt;
    const scalar t = time_.value();

    if (history_.valid())
    {
        history_()
            << t << ' ' << M << ' ' << qIn << ' ' << qOut << ' '
            << fed_ << ' ' << out_ << ' ' << maxSpeed << ' ' << Mzone << ' ' << Mdense
            << endl;
    }

    // A diverged solution can run on with tiny steps and blow the powder out through the outlet;
    // its history would then settle to a loading that means nothing. Any powder at all counts.
    if (maxPowderSpeed_ > 0)
    {
        const scalar fastest = gMax
        (
            pos(alpha.primitiveField() - 0.01)*mag(U.primitiveField())
        );
        if (fastest > maxPowderSpeed_)
        {
            FatalErrorInFunction
                << "the solution diverged: powder moving at " << fastest
                << " m/s at t = " << t << " s, above the bound of "
                << maxPowderSpeed_ << " m/s (ten times the paddle tips' speed"
                << " plus the free-fall speed across the bore). No loading is"
                << " reported. Rerun with a smaller Courant number (--max-courant)"
                << " or with every cell counted (--courant-alpha-min 0)."
                << exit(FatalError);
        }
    }

    if (ts_.empty() || t - ts_.last() >= window_/50)
    {
        ts_.append(t);
        ms_.append(M);
        cs_.append(out_);
        const scalar W = mixload::steady::windowLength
        (
            window_, period_, residenceFraction_, M, feed_
        );
        // Keep the last 2.5 windows: the test reads two.
        label drop = 0;
        while (drop < ts_.size() - 2 && ts_[drop + 1] < t - 2.5*W)
        {
            ++drop;
        }
        if (drop > 0)
        {
            // Copies first: a list assigned from a view of itself would alias.
            const scalarList t2(SubList<scalar>(ts_, ts_.size() - drop, drop));
            const scalarList m2(SubList<scalar>(ms_, ms_.size() - drop, drop));
            const scalarList c2(SubList<scalar>(cs_, cs_.size() - drop, drop));
            ts_ = t2;
            ms_ = m2;
            cs_ = c2;
        }
        std::vector<double> T(ts_.begin(), ts_.end());
        std::vector<double> Ms(ms_.begin(), ms_.end());
        std::vector<double> Cs(cs_.begin(), cs_.end());
        const mixload::steady::Verdict v = mixload::steady::test
        (
            T, Ms, Cs, W, feed_, tol_, flowTol_, minTime_
        );
        if (v.steady && !steady_)
        {
            steady_ = true;
            Info<< type() << ' ' << name() << ": loading steady at t = " << t
                << ": mean " << v.meanLoading << " kg (previous window "
                << v.previousMean << "), outflow " << v.meanOutflow
                << " kg/s for a feed of " << feed_ << " kg/s" << endl;
            if (Pstream::master())
            {
                OFstream os(time_.globalPath()/"postProcessing"/name()/"steady");
                os.precision(12);
                os  << "time " << t << nl
                    << "loading_kg " << v.meanLoading << nl
                    << "previous_kg " << v.previousMean << nl
                    << "outflow_kg_s " << v.meanOutflow << nl
                    << "window " << W << nl
                    << "drift " << v.drift << nl
                    << "flow_error " << v.flowError << nl;
            }
            const_cast<Time&>(time_).writeAndEnd();
        }
    }

    // A run stopped by its cap writes its last state, so that a longer cap resumes from there
    // instead of from the last regular write.
    if (!steady_ && t >= time_.endTime().value() - 0.5*time_.deltaTValue())
    {
        const_cast<Time&>(time_).writeNow();
    }

    setProperty("fed", fed_);
    setProperty("out", out_);
    setProperty("sampleTimes", scalarList(ts_));
    setProperty("sampleLoadings", scalarList(ms_));
    setProperty("sampleOutflows", scalarList(cs_));
    return true;
}


bool Foam::functionObjects::loadingMonitor::write()
{
    return true;
}
