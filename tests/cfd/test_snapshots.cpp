// SPDX-License-Identifier: GPL-3.0-or-later
// Snapshots of real (tiny) runs: the HDF5 file holds what OpenFOAM wrote (to float32 rounding),
// the mesh geometry equals OpenFOAM's own cell volumes and centres, the XDMF sidecar points at
// datasets that exist with the shapes it declares, and damaged files are refused with a clear error.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <regex>

#include <nlohmann/json.hpp>

#include "cli_harness.hpp"
#include "common/atomic_file.hpp"
#include "post/bed_profile.hpp"
#include "post/foam_files.hpp"
#include "store/h5_io.hpp"
#include "post/snapshots.hpp"
#include "store/snapshot_file.hpp"
#include "run/foam_runner.hpp"

using namespace mixload::testing;
namespace fs = std::filesystem;
namespace post = mixload::post;

namespace {

// One stored time of a field, as the tests compare it.
std::vector<double> storedColumn(const fs::path& file, const std::string& field, size_t t) {
    const auto c = mixload::store::SnapshotFile(file).column(field, t);
    return {c.data(), c.data() + c.size()};
}

// One tiny collapse (940 cells, ~3 s) with --snapshots, shared by the tests of this file.
fs::path collapseRun() {
    static const fs::path dir = [] {
        const fs::path out = scratchDir("snapshots-collapse") / "run";
        const auto r = runMixload({"collapse", "--material", "quartz", "--aspect", "2",
                                   "--cells-per-length", "8", "--out", out.string(), "--snapshots",
                                   "--json"});
        EXPECT_EQ(r.rc, 0) << r.err;
        EXPECT_EQ(nlohmann::json::parse(r.out)["snapshots"], (out / "snapshots.h5").string());
        return out;
    }();
    return dir;
}

std::vector<std::string> timesWith(const fs::path& run, const std::vector<std::string>& fields) {
    std::vector<std::string> out;
    for (const auto& t : post::timeDirectories(run)) {
        bool all = true;
        for (const auto& f : fields) all = all && fs::exists(run / t / f);
        if (all) out.push_back(t);
    }
    return out;
}

// Stored float32 is the written value rounded once.
void expectSameField(const std::vector<double>& stored, const std::vector<double>& written) {
    ASSERT_EQ(stored.size(), written.size());
    for (size_t i = 0; i < stored.size(); ++i)
        ASSERT_NEAR(stored[i], written[i], 1e-7 * std::abs(written[i]) + 1e-37) << "value " << i;
}

}  // namespace

TEST(Snapshots, CollapseRoundTripsEveryWrittenTime) {
    const fs::path run = collapseRun();
    const fs::path h5 = run / "snapshots.h5";
    const auto times = timesWith(run, {"alpha.powder", "U", "p"});
    ASSERT_GT(times.size(), 5u);
    const auto info = mixload::store::SnapshotFile(h5).info();
    EXPECT_EQ(info["times"]["count"], times.size());
    EXPECT_EQ(info["cells"], 940);
    EXPECT_EQ(info["provenance"]["schema"], "mixload-snapshots");
    EXPECT_EQ(info["provenance"]["scene_kind"], "collapse2d");
    EXPECT_FALSE(info["provenance"]["scene_hash"].get<std::string>().empty());
    EXPECT_EQ(info["params"]["material.name"], "quartz");
    EXPECT_DOUBLE_EQ(info["params"]["aspect"].get<double>(), 2.0);
    const auto mesh = post::readPolyMesh(run / "constant" / "polyMesh");
    for (size_t i : {size_t(0), times.size() / 2, times.size() - 1}) {
        for (const char* f : {"alpha.powder", "U", "p"})
            expectSameField(storedColumn(h5, f, i),
                            post::readInternalField(run / times[i] / f, mesh.nCells).values);
    }
    // Powder volume from the file equals the run's own: alpha x V summed.
    auto file = mixload::h5::openFile(h5);
    const auto v = mixload::h5::readDoubles(file, "/mesh/cell_volumes");
    const auto a0 = storedColumn(h5, "alpha", 0), a1 = storedColumn(h5, "alpha", times.size() - 1);
    double m0 = 0, m1 = 0;
    for (size_t c = 0; c < v.size(); ++c) m0 += a0[c] * v[c], m1 += a1[c] * v[c];
    EXPECT_NEAR(m1, m0, 1e-3 * m0);
    EXPECT_TRUE(mixload::h5::exists(file, "/history/collapse"));
}

TEST(Snapshots, MeshGeometryEqualsOpenFoams) {
    const fs::path run = collapseRun();
    // OpenFOAM's own function objects on a copy of the case (they write into the time directory).
    const fs::path copy = scratchDir("snapshots-geometry") / "case";
    fs::create_directories(copy);
    for (const char* d : {"constant", "system", "0"}) fs::copy(run / d, copy / d, fs::copy_options::recursive);
    mixload::run::runUtility(copy, {"postProcess", "-func", "writeCellVolumes", "-time", "0"});
    mixload::run::runUtility(copy, {"postProcess", "-func", "writeCellCentres", "-time", "0"});
    auto file = mixload::h5::openFile(run / "snapshots.h5");
    const auto v = mixload::h5::readDoubles(file, "/mesh/cell_volumes");
    const auto c = mixload::h5::readDoubles(file, "/mesh/cell_centres");
    const auto vf = post::readInternalField(copy / "0" / "V", static_cast<int32_t>(v.size()));
    const auto cf = post::readInternalField(copy / "0" / "C", static_cast<int32_t>(v.size()));
    ASSERT_EQ(vf.values.size(), v.size());
    ASSERT_EQ(cf.values.size(), c.size());
    // The collapse case writes 8 significant digits: equal to that.
    for (size_t i = 0; i < v.size(); ++i) ASSERT_NEAR(v[i], vf.values[i], 5e-8 * vf.values[i]) << i;
    for (size_t i = 0; i < c.size(); ++i)
        ASSERT_NEAR(c[i], cf.values[i], 5e-8 * std::abs(cf.values[i]) + 1e-15) << i;
}

TEST(Snapshots, XdmfReferencesExistingDatasetsWithTheirShapes) {
    const fs::path run = collapseRun();
    const std::string xmf = mixload::readFile(run / "snapshots.xmf");
    auto file = mixload::h5::openFile(run / "snapshots.h5");
    const std::regex item("<DataItem Dimensions=\"([0-9 ]+)\"[^>]*Format=\"HDF\">([^:<]+):([^<]+)</DataItem>");
    size_t refs = 0;
    for (auto it = std::sregex_iterator(xmf.begin(), xmf.end(), item); it != std::sregex_iterator(); ++it) {
        const auto& m = *it;
        EXPECT_EQ(m[2].str(), "snapshots.h5");
        ASSERT_TRUE(mixload::h5::exists(file, m[3].str())) << m[3];
        std::string dims;
        for (auto d : mixload::h5::shape(mixload::h5::openDataset(file, m[3].str())))
            dims += (dims.empty() ? "" : " ") + std::to_string(d);
        EXPECT_EQ(m[1].str(), dims) << m[3];
        ++refs;
    }
    const auto times = mixload::store::SnapshotFile(run / "snapshots.h5").info(false)["times"]["count"].get<size_t>();
    EXPECT_EQ(refs, times * 5);  // centres, volumes, alpha, U, p per time
    EXPECT_EQ(std::count(xmf.begin(), xmf.end(), '\n') > 10, true);
}

TEST(Snapshots, DamagedFilesAreRefusedClearly) {
    const fs::path run = collapseRun();
    const fs::path dir = scratchDir("snapshots-damaged");
    const std::string bytes = mixload::readFile(run / "snapshots.h5");
    const fs::path cut = dir / "cut.h5", flipped = dir / "flipped.h5";
    std::ofstream(cut, std::ios::binary).write(bytes.data(), static_cast<long>(bytes.size() / 2));
    auto r = runMixload({"snapshots", "info", cut.string()});
    EXPECT_EQ(r.rc, 2) << r.out;
    EXPECT_NE(r.err.find("truncated or corrupt"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(cut.string()), std::string::npos) << r.err;

    // Overwrite a stretch in the middle of the data: a checksum (or the structure) must fail.
    std::string bad = bytes;
    for (size_t i = bad.size() / 2; i < bad.size() / 2 + 256; ++i) bad[i] = static_cast<char>(~bad[i]);
    std::ofstream(flipped, std::ios::binary).write(bad.data(), static_cast<long>(bad.size()));
    r = runMixload({"snapshots", "info", flipped.string(), "--json"});
    EXPECT_EQ(r.rc, 2) << r.out;
    EXPECT_TRUE(r.out.empty()) << "printed a result from a damaged file";
    EXPECT_NE(r.err.find(flipped.string()), std::string::npos) << r.err;

    r = runMixload({"snapshots", "info", (dir / "missing.h5").string()});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("no such file"), std::string::npos) << r.err;
}

TEST(Snapshots, ExportOptionsAndBadInput) {
    const fs::path run = collapseRun();
    const fs::path dir = scratchDir("snapshots-export");
    const fs::path out = dir / "every3.h5";
    auto r = runMixload({"snapshots", "export", run.string(), "-o", out.string(), "--every", "3",
                         "--fields", "alpha,p_rgh", "--float64", "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    const auto all = timesWith(run, {"alpha.powder", "p_rgh"});
    EXPECT_EQ(j["times"], (all.size() - 1) / 3 + 1 + ((all.size() - 1) % 3 ? 1 : 0));
    EXPECT_EQ(j["field_precision"], "float64");
    EXPECT_TRUE(fs::exists(dir / "every3.xmf"));
    // float64 is exact.
    const auto mesh = post::readPolyMesh(run / "constant" / "polyMesh");
    EXPECT_EQ(storedColumn(out, "p_rgh", j["times"].get<size_t>() - 1),
              post::readInternalField(run / all.back() / "p_rgh", mesh.nCells).values);

    const auto rejected = [&](std::vector<std::string> args, const std::string& needle) {
        const auto rr = runMixload(args);
        EXPECT_EQ(rr.rc, 2) << rr.err;
        EXPECT_NE(rr.err.find(needle), std::string::npos) << rr.err;
    };
    rejected({"snapshots", "export", dir.string(), "-o", (dir / "x.h5").string()}, "RUN_DIR");
    rejected({"snapshots", "export", run.string(), "-o", (dir / "y.h5").string(), "--fields", "T"}, "fields");
    rejected({"snapshots", "export", run.string(), "-o", (dir / "z.txt").string()}, ".h5");
    rejected({"snapshots", "export", run.string(), "-o", (dir / "w.h5").string(), "--every", "0"}, "every");
    for (const char* f : {"x.h5", "y.h5", "z.txt", "w.h5"}) EXPECT_FALSE(fs::exists(dir / f)) << f;
    // No temporary file survives anywhere.
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_EQ(e.path().string().find(".tmp."), std::string::npos) << e.path();
}

TEST(Snapshots, ProvenanceAbove64KiBRoundTrips) {
    // A campaign's kept progress carries each stopped point's loading-monitor history (up to 1 000
    // samples of three series): more than the 64 KiB an HDF5 attribute may hold in the default
    // format's object header.
    const mixload::store::SnapshotFile source(collapseRun() / "snapshots.h5");
    const Eigen::MatrixXd alpha = source.column("alpha", 0);
    std::string big;
    for (int i = 0; i < 20000; ++i) big += std::to_string(0.1 * i) + ' ';
    ASSERT_GT(big.size(), 100000u);
    const fs::path file = scratchDir("snapshots-big-attr") / "big.h5";
    mixload::store::writeDerivedSnapshots(source, {1.0}, {{"alpha", alpha}}, {{"kind", "test"}, {"monitor", big}}, file);
    EXPECT_EQ(mixload::store::SnapshotFile(file).provenance().at("monitor").get<std::string>(), big);
}

TEST(Snapshots, FunctionObjectStateReadsNumbersAndLists) {
    // As v1912 writes <time>/uniform/functionObjects/functionObjectProperties: short lists inline,
    // long ones one value per line, equal ones as N{x}.
    const fs::path file = scratchDir("fo-state") / "functionObjectProperties";
    std::ofstream(file) << "FoamFile\n{\n    version 2.0;\n    format ascii;\n    class dictionary;\n"
                           "    object functionObjectProperties;\n}\n// comment\n\n"
                           "other\n{\n    fed 9;\n}\n"
                           "loading\n{\n    fed             0.0036;\n    out 4e-3;\n"
                           "    sampleTimes     3 ( 0.1 0.2 0.3 );\n"
                           "    sampleLoadings  List<scalar> \n3\n(\n1\n2\n3\n)\n;\n"
                           "    sampleOutflows  3{0};\n}\n";
    const auto s = post::readFunctionObjectState(file, "loading");
    EXPECT_EQ(s.at("fed"), std::vector<double>{0.0036});
    EXPECT_EQ(s.at("out"), std::vector<double>{4e-3});
    EXPECT_EQ(s.at("sampleTimes"), (std::vector<double>{0.1, 0.2, 0.3}));
    EXPECT_EQ(s.at("sampleLoadings"), (std::vector<double>{1, 2, 3}));
    EXPECT_EQ(s.at("sampleOutflows"), (std::vector<double>{0, 0, 0}));
    EXPECT_THROW(post::readFunctionObjectState(file, "absent"), std::runtime_error);
}

// The bed profile of the shipped 1 cm reference snapshot (gcm250-v2, 611 s): its layers add up to
// the loading and the dense loading that the solver's own monitor wrote at that time (alpha stored
// in float32), one layer per axial station of the O-grid, in order. The CLI names a bad time.
TEST(Snapshots, BedProfileAddsUpToTheMonitorsLoading) {
    const std::string file = MIXLOAD_SOURCE_DIR "/data/snapshots/mixer-gcm250-v2-reference-4af44e4a3db3f89a.h5";
    const mixload::store::SnapshotFile f(file);
    const auto p = mixload::post::bedProfile(f, f.times().size() - 1);
    const auto history = mixload::h5::readDoubles(mixload::h5::openFile(file), "/history/loading");
    const size_t last = history.size() / 9 - 1;
    ASSERT_NEAR(history[9 * last], p.time, 1e-6);
    EXPECT_NEAR(p.loadingKg, history[9 * last + 1], 1e-6 * history[9 * last + 1]);
    double mass = 0, dense = 0;
    for (size_t k = 0; k < p.layers.size(); ++k) {
        mass += p.layers[k].massKg;
        dense += p.layers[k].denseKg;
        EXPECT_LE(p.layers[k].denseKg, p.layers[k].massKg);
        if (k) EXPECT_GT(p.layers[k].x, p.layers[k - 1].x);
    }
    EXPECT_NEAR(mass, p.loadingKg, 1e-12);
    EXPECT_NEAR(dense, history[9 * last + 8], 1e-5 * history[9 * last + 8]);
    EXPECT_EQ(p.layers.size(), 32u);  // the 1 cm O-grid's axial stations over 0.3 m

    const fs::path dir = scratchDir("bed-profile");
    auto r = runMixload({"snapshots", "profile", file, file, "--plot", dir.string(), "--json"});
    ASSERT_EQ(r.rc, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_EQ(j["profiles"].size(), 2u);
    EXPECT_NEAR(j["profiles"][1]["loading_kg"].get<double>(), p.loadingKg, 1e-12);
    EXPECT_TRUE(fs::exists(dir / "profile.dat"));
    if (j.contains("plot")) EXPECT_GT(fs::file_size(j["plot"].get<std::string>()), 1000u);
    r = runMixload({"snapshots", "profile", file, "--time", "5000"});
    EXPECT_EQ(r.rc, 2);
    EXPECT_NE(r.err.find("time = 5000"), std::string::npos) << r.err;
}
