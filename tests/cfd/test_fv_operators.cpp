// SPDX-License-Identifier: GPL-3.0-or-later
// The reduced models' finite-volume operators (rom/operators/fv_operators) against OpenFOAM's own fvc on the
// same stored fields: a tiny real collapse (2D, ASCII fields) and a tiny real mixer (3D O-grid,
// binary fields, rotating walls, inlet and outlet patches), and the mu(I) viscosity against the
// solver's own viscosity model. OpenFOAM's results come from
// mixloadFvcRef (fullcfd/verify), written in binary; every operator agrees to 1e-10 relative.
// The mixer's steady powder transport (the reduced steady model's step) is checked on the same kind
// of run: it conserves powder, and the flux it rebuilds from U is the solver's.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "post/foam_files.hpp"
#include "rom/operators/fv_operators.hpp"
#include "rom/operators/granular_viscosity.hpp"
#include "rom/operators/steady_transport.hpp"
#include "run/foam_runner.hpp"
#include "store/snapshot_file.hpp"

using namespace mixload;
using namespace mixload::testing;
namespace fs = std::filesystem;

namespace {
// max |a - ref| / max |ref|, printed so that the README can quote it.
double relErr(const Eigen::VectorXd& a, const std::vector<double>& ref) {
    EXPECT_EQ(static_cast<size_t>(a.size()), ref.size());
    if (static_cast<size_t>(a.size()) != ref.size()) return 1;
    const Eigen::Map<const Eigen::VectorXd> b(ref.data(), static_cast<Eigen::Index>(ref.size()));
    const double e = (a - b).cwiseAbs().maxCoeff() / std::max(b.cwiseAbs().maxCoeff(), 1e-300);
    std::cout << "relative difference " << e << '\n';
    return e;
}

Eigen::VectorXd flat(const rom::Vectors& v) { return Eigen::Map<const Eigen::VectorXd>(v.data(), v.size()); }


// Exports the run's fields in float64 with phi, runs OpenFOAM's operators at the time nearest the
// middle of the run, and checks each of ours against them.
void checkOperators(const fs::path& run) {
    const fs::path h5 = run / "operators.h5";
    auto r = runMixload({"snapshots", "export", run.string(), "-o", h5.string(), "--fields", "alpha,U,p,phi", "--float64"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const store::SnapshotFile f(h5);
    ASSERT_GE(f.times().size(), 1u);
    const size_t t = f.times().size() / 2;
    std::string timeName;
    for (const auto& name : post::timeDirectories(run))
        if (std::abs(std::stod(name) - f.times()[t]) < 1e-9 * std::max(1.0, f.times()[t])) timeName = name;
    ASSERT_FALSE(timeName.empty());
    run::runUtility(run, {MIXLOAD_FVC_REF, "-time", timeName});

    const auto m = rom::FvMesh::fromCase(f);
    const auto polyMesh = post::readPolyMesh(run / "constant" / "polyMesh");
    const fs::path dir = run / timeName;
    const auto vol = [&](const std::string& name) { return post::readInternalField(dir / name, polyMesh.nCells).values; };
    const Eigen::VectorXd alpha = f.column("alpha", t), alphaB = f.boundaryColumn("alpha", t);

    // Linear weights and face values (internal faces; the boundary faces carry the patch values).
    const auto refW = post::readSurfaceField(dir / "fvcRef.weights", polyMesh);
    EXPECT_LT(relErr(m.weights, std::vector<double>(refW.begin(), refW.begin() + m.internalFaces)), 1e-10) << "weights";
    EXPECT_LT(relErr(rom::interpolate(m, alpha, alphaB), post::readSurfaceField(dir / "fvcRef.interpolate.alpha", polyMesh)),
              1e-10)
        << "interpolate";
    EXPECT_LT(relErr(flat(rom::grad(m, alpha, alphaB)), vol("fvcRef.grad.alpha")), 1e-10) << "grad";
    EXPECT_LT(relErr(rom::div(m, f.faceColumn("phi", t)), vol("fvcRef.div.phi")), 1e-10) << "div";
    EXPECT_LT(relErr(rom::laplacian(m, alpha, alphaB), vol("fvcRef.laplacian.alpha")), 1e-10) << "laplacian";
    EXPECT_LT(relErr(rom::strainRate(m, rom::asVectors(f.column("U", t)), rom::asVectors(f.boundaryColumn("U", t))),
                     vol("fvcRef.strainRate")),
              1e-10)
        << "strain rate";
    EXPECT_LT(relErr(flat(rom::reconstruct(m, f.faceColumn("phi", t))), vol("fvcRef.reconstruct.phi")), 1e-10)
        << "reconstruct";
    const Eigen::VectorXd p = f.column("p", t);
    EXPECT_LT(relErr(rom::laplacian(m, rom::interpolate(m, p, f.boundaryColumn("p", t)), alpha, alphaB),
                     vol("fvcRef.laplacianP.alpha")),
              1e-10)
        << "laplacian with a face diffusivity";
    const auto law = rom::GranularLaw::fromCase(f);
    const Eigen::VectorXd sr = rom::strainRate(m, rom::asVectors(f.column("U", t)), rom::asVectors(f.boundaryColumn("U", t)));
    EXPECT_LT(relErr(law.nu(sr, f.column("p", t)), vol("fvcRef.nu.powder")), 1e-10) << "mu(I) viscosity";
}
}  // namespace

TEST(FvOperators, AgreeWithOpenFoamOnACollapse) {
    const fs::path run = scratchDir("fvops-collapse") / "run";
    const auto r = runMixload({"collapse", "--material", "quartz", "--aspect", "2", "--cells-per-length", "8", "--out",
                               run.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    checkOperators(run);
}

TEST(FvOperators, AgreeWithOpenFoamOnAMixer) {
    const fs::path run = scratchDir("fvops-mixer") / "run";
    const auto r = runMixload({"mixer", "--scene", kGcm250At1cm, "--cell-size", "0.01", "--end-time", "0.05", "--out",
                               run.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    checkOperators(run);
}

TEST(SteadyTransport, ConservesPowderAndRebuildsTheSolversFlux) {
    const fs::path run = scratchDir("steady-mixer") / "run";
    auto r = runMixload({"mixer", "--scene", kGcm250At1cm, "--cell-size", "0.01", "--end-time", "0.05", "--out", run.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const fs::path h5 = run / "steady.h5";
    r = runMixload({"snapshots", "export", run.string(), "-o", h5.string(), "--fields", "alpha,U,phi", "--float64"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const store::SnapshotFile f(h5);
    const auto m = rom::FvMesh::fromCase(f);
    // The frozen rotor as the solver read it: a zone inside the mesh, turning at the scene's speed.
    const auto zones = f.mrfZones();
    ASSERT_EQ(zones.size(), 1u);
    EXPECT_GT(zones[0].cells.size(), 0u);
    EXPECT_LT(zones[0].cells.size(), static_cast<size_t>(m.cells));
    EXPECT_NEAR(zones[0].omega, f.params().at("rpm").get<double>() * 2 * M_PI / 60, 1e-9 * zones[0].omega);

    const size_t t = f.times().size() - 1;
    const Eigen::VectorXd phi = f.faceColumn("phi", t);
    const auto s = rom::steadyPowder(m, phi, {{"inlet", 1.0}});
    std::cout << "steady powder: inflow " << s.inflow << " m3/s, outflow " << s.outflow << ", residual " << s.residual << '\n';
    EXPECT_LT(s.residual, 1e-10);
    EXPECT_GT(s.inflow, 0);
    EXPECT_LT(std::abs(s.outflow - s.inflow) / s.inflow, 1e-3) << "the steady powder leaves as it enters";
    EXPECT_GT(s.alpha.minCoeff(), -1e-9);
    EXPECT_LT(s.alpha.maxCoeff(), 1 + 1e-9);

    const Eigen::VectorXd rebuilt = rom::fluxFromVelocity(m, rom::asVectors(f.column("U", t)),
                                                          rom::asVectors(f.boundaryColumn("U", t)), zones, "outlet");
    const Eigen::VectorXd sources = rom::div(m, rebuilt).cwiseProduct(m.V);
    EXPECT_LT(sources.cwiseAbs().maxCoeff() / rebuilt.cwiseAbs().maxCoeff(), 1e-10) << "divergence-free";
    const auto in = m.internalFaces;
    const double err = (rebuilt.head(in) - phi.head(in)).norm() / phi.head(in).norm();
    std::cout << "flux rebuilt from U against phi: relative L2 " << err << '\n';
    EXPECT_LT(err, 0.1);
    // Without the rotor's frame the rebuilt flux is the absolute one, several times further off.
    const Eigen::VectorXd absolute = rom::fluxFromVelocity(m, rom::asVectors(f.column("U", t)),
                                                           rom::asVectors(f.boundaryColumn("U", t)), {}, "outlet");
    EXPECT_GT((absolute.head(in) - phi.head(in)).norm() / phi.head(in).norm(), 3 * err);

    r = runMixload({"rom", "steady", h5.string(), "--mean-last", "2", "--march", "0.01", "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    // The march starts from the run's last state and keeps the powder's fraction bounded.
    ASSERT_TRUE(j.contains("march"));
    EXPECT_GT(j["march"]["steps"].get<long>(), 0);
    EXPECT_NEAR(j["march"]["history"].front()["loading_kg"].get<double>(), j["times"].back()["loading_kg"].get<double>(), 1e-12);
    EXPECT_GT(j["mean_flux"]["steady_kg"].get<double>(), 0);
    EXPECT_EQ(runMixload({"rom", "steady", h5.string(), "--march", "-1"}).rc, 2);
    EXPECT_TRUE(j["from_phi"].get<bool>());
    EXPECT_TRUE(j["from_u"].get<bool>());
    ASSERT_FALSE(j["times"].empty());
    EXPECT_GT(j["times"].back()["steady_from_phi_kg"].get<double>(), 0);
    // A file that is not there is refused with a clear error.
    r = runMixload({"rom", "steady", (run / "missing.h5").string()});
    EXPECT_EQ(r.rc, 2);
}
