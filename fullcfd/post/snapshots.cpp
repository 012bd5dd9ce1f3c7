// SPDX-License-Identifier: GPL-3.0-or-later
#include "post/snapshots.hpp"

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

#include "common/atomic_file.hpp"
#include "common/input_error.hpp"
#include "post/foam_files.hpp"
#include "store/h5_io.hpp"
#include "store/snapshot_file.hpp"
#include "store/xdmf.hpp"
#include "post/mesh_geometry.hpp"
#include "post/monitor_history.hpp"

namespace mixload::post {

namespace fs = std::filesystem;

namespace {


std::string unitOf(const std::string& field) {
    static const std::map<std::string, std::string> units{
        {"alpha.powder", "1"}, {"U", "m/s"}, {"p", "Pa"}, {"p_rgh", "Pa"}, {"nu", "m2/s"}};
    const auto it = units.find(field);
    return it == units.end() ? "see OpenFOAM dimensions" : it->second;
}

std::vector<double> flatten(const std::vector<Vec3>& v) {
    std::vector<double> out(v.size() * 3);
    for (size_t i = 0; i < v.size(); ++i)
        for (int k = 0; k < 3; ++k) out[3 * i + k] = v[i][k];
    return out;
}

// Scene inputs as /params attributes: nested keys joined with '.', units are in the key names.
void writeParams(hid_t group, const nlohmann::json& j, const std::string& prefix) {
    for (const auto& [k, v] : j.items()) {
        const std::string name = prefix.empty() ? k : prefix + "." + k;
        if (v.is_object()) writeParams(group, v, name);
        else if (v.is_number()) h5::attr(group, name, v.get<double>());
        else if (v.is_boolean()) h5::attr(group, name, static_cast<long long>(v.get<bool>()));
        else if (v.is_string()) h5::attr(group, name, v.get<std::string>());
        else h5::attr(group, name, v.dump());
    }
}

struct History {
    std::string columns;
    std::vector<std::vector<double>> rows;
};

// Every monitor under postProcessing/, restarts merged.
std::map<std::string, History> readHistories(const fs::path& runDir) {
    std::map<std::string, History> out;
    const fs::path pp = runDir / "postProcessing";
    if (!fs::exists(pp)) return out;
    for (const auto& mon : fs::directory_iterator(pp)) {
        if (!mon.is_directory()) continue;
        std::string file;
        for (const auto& seg : fs::directory_iterator(mon.path()))
            if (seg.is_directory())
                for (const auto& f : fs::directory_iterator(seg.path()))
                    if (f.path().extension() == ".dat") file = f.path().filename();
        if (file.empty()) continue;
        struct Row {
            double t = 0;
            std::vector<double> v;
        };
        const auto rows = readSegments<Row>(mon.path(), file, [](std::istringstream& ls, Row& r) {
            double x;
            while (ls >> x) r.v.push_back(x);
            if (r.v.empty()) return false;
            r.t = r.v[0];
            return true;
        });
        History h;
        for (const auto& seg : fs::directory_iterator(mon.path())) {
            std::ifstream is(seg.path() / file);
            std::string line;
            if (std::getline(is, line) && !line.empty() && line[0] == '#') {
                h.columns = line.substr(line.find_first_not_of("# "));
                break;
            }
        }
        size_t width = rows.empty() ? 0 : rows.front().v.size();
        for (const auto& r : rows)
            if (r.v.size() == width) h.rows.push_back(r.v);
        out[mon.path().filename()] = h;
    }
    return out;
}


}  // namespace

nlohmann::json exportSnapshots(const SnapshotExport& e) {
    const fs::path run = e.runDir;
    if (!fs::is_directory(run / "constant" / "polyMesh") || !fs::exists(run / "scene.json"))
        throw InputError("RUN_DIR", run.string(), "a mixload run directory (scene.json, constant/polyMesh)");
    requireRange("every", e.every, 1, 1e6);
    if (e.fields.empty()) throw InputError("fields", "(none)", "at least one field, e.g. alpha,U,p");
    const fs::path out = e.output.empty() ? run / "snapshots.h5" : e.output;
    if (out.extension() != ".h5") throw InputError("output", out.string(), "a file name ending in .h5");
    if (!out.parent_path().empty() && !fs::is_directory(out.parent_path()))
        throw InputError("output", out.string(), "a file in an existing directory");

    const auto times = timeDirectories(run);
    std::vector<std::string> names;
    for (const auto& f : e.fields) names.push_back(store::storedFieldName(f));
    for (const auto& f : names) {
        bool found = false;
        for (const auto& t : times) found = found || fs::exists(run / t / f);
        if (!found)
            throw InputError("fields", f, "fields the run wrote (e.g. alpha, U, p, p_rgh)");
    }
    // Every K-th time, and always the last (the final state is what campaigns are about).
    std::vector<std::string> picked, skipped;
    for (size_t i = 0; i < times.size(); ++i) {
        if (i % e.every != 0 && i + 1 != times.size()) continue;
        bool all = true;
        for (const auto& f : names) all = all && fs::exists(run / times[i] / f);
        (all ? picked : skipped).push_back(times[i]);
    }
    if (picked.empty())
        throw InputError("RUN_DIR", run.string(), "a run with at least one time holding every requested field");

    const FoamMesh mesh = readPolyMesh(run / "constant" / "polyMesh");
    const MeshGeometry geo = meshGeometry(mesh);
    bool moving = false;
    for (const auto& t : picked) moving = moving || fs::exists(run / t / "polyMesh" / "points");
    const auto sceneJson = nlohmann::json::parse(readFile(run / "scene.json"));
    nlohmann::json solverProvenance;
    if (fs::exists(run / "result.json")) {
        const auto r = nlohmann::json::parse(readFile(run / "result.json"));
        for (const char* k : {"mixload_version", "git_commit", "openfoam_version"})
            if (r.contains(k)) solverProvenance[k] = r[k];
    }

    std::vector<std::pair<std::string, int>> written;
    std::vector<double> timeValues;
    h5::writeFileAtomically(out, [&](hid_t file) {
        store::writeFileHeader(file, store::kSnapshotSchema, store::kSnapshotSchemaVersion);
        h5::attr(file, "openfoam_version", std::string(MIXLOAD_OPENFOAM_VERSION));
        h5::attr(file, "scene_hash", sceneJson.value("hash", std::string()));
        h5::attr(file, "scene_kind", sceneJson["scene"].value("scene", std::string()));
        h5::attr(file, "run_dir", fs::absolute(run).string());
        h5::attr(file, "solver_provenance", solverProvenance.dump());
        h5::attr(file, "field_precision", std::string(e.float64 ? "float64" : "float32"));
        h5::attr(file, "mesh_moves", static_cast<long long>(moving));

        {
            auto params = h5::createGroup(file, "params");
            writeParams(params, sceneJson["scene"], "");
            h5::attr(params, "scene_json", sceneJson.dump());
            // The viscosity coefficients exactly as the solver read them (reduced models evaluate
            // the same law).
            if (fs::exists(run / "constant" / "transportProperties")) {
                const auto t = readPowderTransport(run);
                auto g = h5::createGroup(params, "powder_transport");
                h5::attr(g, "model", t.model);
                for (const auto& [k, v] : t.values) h5::attr(g, k, v);
            }
        }
        {
            auto g = h5::createGroup(file, "mesh");
            const hsize_t nP = mesh.points.size(), nF = mesh.nFaces(), nC = mesh.nCells;
            h5::write(g, "points", {nP, 3}, flatten(mesh.points));
            h5::write(g, "face_offsets", mesh.faceOffsets);
            h5::write(g, "face_points", mesh.facePoints);
            h5::write(g, "owner", mesh.owner);
            h5::write(g, "neighbour", mesh.neighbour);
            h5::write(g, "face_centres", {nF, 3}, flatten(geo.faceCentres));
            h5::write(g, "face_areas", {nF, 3}, flatten(geo.faceAreas));
            h5::write(g, "cell_centres", {nC, 3}, flatten(geo.cellCentres));
            h5::write(g, "cell_volumes", {nC}, geo.cellVolumes);
            auto patches = h5::createGroup(g, "patches");
            for (const auto& p : mesh.patches) {
                auto pg = h5::createGroup(patches, p.name);
                h5::attr(pg, "type", p.type);
                h5::attr(pg, "start_face", static_cast<long long>(p.start));
                h5::attr(pg, "n_faces", static_cast<long long>(p.size));
            }
            // The cell zones and the frozen-rotor zones' rotation: a mixer's powder is carried by
            // the flux relative to the rotor there, which a reduced model rebuilding a flux from U
            // needs (rom/operators/steady_transport).
            const auto zones = readCellZones(run / "constant" / "polyMesh");
            if (!zones.empty()) {
                auto zg = h5::createGroup(g, "zones");
                for (const auto& [name, cells] : zones) h5::write(zg, name, cells);
            }
            const auto mrf = readMrfZones(run);
            if (!mrf.empty()) {
                auto mg = h5::createGroup(g, "mrf");
                for (const auto& z : mrf) {
                    auto zg = h5::createGroup(mg, z.name);
                    h5::attr(zg, "cell_zone", z.cellZone);
                    h5::attr(zg, "omega_rad_s", z.omega);
                    h5::write(zg, "origin", {3}, {z.origin.begin(), z.origin.end()});
                    h5::write(zg, "axis", {3}, {z.axis.begin(), z.axis.end()});
                }
            }
        }
        for (const auto& t : picked) timeValues.push_back(std::stod(t));
        {
            auto fg = h5::createGroup(file, "fields");
            const hsize_t nT = picked.size(), nC = mesh.nCells;
            const auto stored = e.float64 ? h5::Stored::Float64 : h5::Stored::Float32;
            // Each field's values on the non-empty patches' faces go to /boundary (what operators
            // need there), read from the same file as its internal field.
            auto bg = h5::createGroup(file, "boundary");
            hsize_t nB = 0;
            for (const auto& p : mesh.patches)
                if (p.type != "empty") nB += static_cast<hsize_t>(p.size);
            for (const auto& f : names) {
                if (f == "phi") continue;  // a face field: /faces below
                // The first time read tells scalar or vector; the datasets are made from it.
                h5::Handle d, bd;
                int comps = 0;
                // A time whose file lacks a patch value (mixload's own initial fields omit some) is
                // stored as NaN and named, never filled in.
                nlohmann::json missing = nlohmann::json::object();
                for (size_t i = 0; i < picked.size(); ++i) {
                    const fs::path src = run / picked[i] / f;
                    const auto v = readInternalField(src, mesh.nCells);
                    if (i == 0) {
                        comps = v.components;
                        d = h5::createDataset(fg, f, comps == 1 ? std::vector<hsize_t>{nT, nC}
                                                                : std::vector<hsize_t>{nT, nC, 3},
                                              stored, true);
                        h5::attr(d, "units", unitOf(f));
                        h5::attr(d, "source", std::string("OpenFOAM <time>/") + f + ", internal field");
                        bd = h5::createDataset(bg, f, comps == 1 ? std::vector<hsize_t>{nT, nB}
                                                                 : std::vector<hsize_t>{nT, nB, 3},
                                               stored, true);
                        h5::attr(bd, "source", std::string("OpenFOAM <time>/") + f +
                                                   ", boundaryField of the non-empty patches");
                    } else if (v.components != comps) {
                        throw std::runtime_error(f + " changes type over time");
                    }
                    h5::writeRow(d, i, v.values);
                    std::vector<double> bv;
                    try {
                        bv = readBoundaryValues(src, mesh, v, geo.faceAreas);
                    } catch (const std::runtime_error& ex) {
                        missing[picked[i]] = ex.what();
                        bv.assign(nB * static_cast<hsize_t>(comps), std::nan(""));
                    }
                    h5::writeRow(bd, i, bv);
                }
                h5::attr(bd, "missing_times", missing.dump());
                written.emplace_back(f, comps);
            }
            // Face fields (phi): internal faces, then the non-empty patches' faces.
            if (std::find(names.begin(), names.end(), "phi") != names.end()) {
                auto faces = h5::createGroup(file, "faces");
                h5::Handle d;
                for (size_t i = 0; i < picked.size(); ++i) {
                    const auto v = readSurfaceField(run / picked[i] / "phi", mesh);
                    if (i == 0) {
                        d = h5::createDataset(faces, "phi", {nT, v.size()}, stored, true);
                        h5::attr(d, "units", std::string("m3/s"));
                        h5::attr(d, "source", std::string("OpenFOAM <time>/phi: internal faces, then the non-empty patches' faces"));
                    }
                    h5::writeRow(d, i, v);
                }
            }
            if (moving) {
                auto d = h5::createDataset(fg, "cell_centres", {nT, nC, 3}, h5::Stored::Float64, true);
                h5::attr(d, "units", std::string("m"));
                for (size_t i = 0; i < picked.size(); ++i) {
                    const fs::path pts = run / picked[i] / "polyMesh" / "points";
                    const auto g = fs::exists(pts) ? meshGeometry(mesh, readPoints(pts)) : geo;
                    h5::writeRow(d, i, flatten(g.cellCentres));
                }
            }
        }
        h5::write(file, "time", {timeValues.size()}, timeValues);
        {
            auto hg = h5::createGroup(file, "history");
            for (const auto& [name, h] : readHistories(run)) {
                const hsize_t rows = h.rows.size(), cols = rows ? h.rows[0].size() : 0;
                std::vector<double> flat;
                for (const auto& r : h.rows) flat.insert(flat.end(), r.begin(), r.end());
                if (rows == 0) continue;
                h5::write(hg, name, {rows, cols}, flat);
                auto d = h5::openDataset(hg, name);
                h5::attr(d, "columns", h.columns);
                // DESIGN.md's /loading: the mixer's loading history at the top level.
                if (name == "loading")
                    H5Lcreate_hard(hg, name.c_str(), file, "/loading", H5P_DEFAULT, H5P_DEFAULT);
            }
        }
    });
    fs::path xdmf = out;
    xdmf.replace_extension(".xmf");
    store::writeXdmf(xdmf, out.filename().string(), timeValues, mesh.nCells, written, e.float64, moving);

    nlohmann::json fieldNames = nlohmann::json::array();
    for (const auto& w : written) fieldNames.push_back(w.first);
    return {{"file", fs::absolute(out).string()},
            {"xdmf", fs::absolute(xdmf).string()},
            {"times", timeValues.size()},
            {"skipped_times", skipped},
            {"cells", mesh.nCells},
            {"fields", fieldNames},
            {"field_precision", e.float64 ? "float64" : "float32"},
            {"mesh_moves", moving},
            {"bytes", fs::file_size(out)}};
}

}  // namespace mixload::post
