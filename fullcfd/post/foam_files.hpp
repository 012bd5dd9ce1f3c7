// SPDX-License-Identifier: GPL-3.0-or-later
// Reads what OpenFOAM wrote (polyMesh and internal fields, ascii or binary with 32-bit labels and
// 64-bit scalars, as Debian's build writes them) without linking OpenFOAM, so the snapshot export
// runs in the C++20 side and can be unit-tested on real run directories.
#pragma once
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace mixload::post {

using Vec3 = std::array<double, 3>;

struct FoamPatch {
    std::string name, type;
    int32_t start = 0, size = 0;
};

struct FoamMesh {
    std::vector<Vec3> points;
    std::vector<int32_t> faceOffsets;  // face f uses facePoints[faceOffsets[f] .. faceOffsets[f+1])
    std::vector<int32_t> facePoints;
    std::vector<int32_t> owner, neighbour;  // neighbour: internal faces only
    std::vector<FoamPatch> patches;
    int32_t nCells = 0;
    size_t nFaces() const { return owner.size(); }
};

// Reads constant/polyMesh (or any polyMesh directory). Throws std::runtime_error naming the file
// on anything malformed or inconsistent.
FoamMesh readPolyMesh(const std::filesystem::path& polyMeshDir);

// Reads only the points of a polyMesh directory (a moving mesh writes them at every time).
std::vector<Vec3> readPoints(const std::filesystem::path& pointsFile);

// The internal field of a volume field file: nCells values (scalars) or nCells x 3 (vectors),
// flattened row-major. "uniform" values are expanded.
struct FoamField {
    int components = 1;
    std::vector<double> values;
};
FoamField readInternalField(const std::filesystem::path& file, int32_t nCells);

// The values of a volume field on every non-empty patch's faces, in mesh patch order (the boundary
// faces a finite-volume operator sees), components together per face: the written `value` where
// the patch has one, else the owner cell's value (zeroGradient), zero (noSlip) or the cell value
// without its normal component (slip, symmetry: faceAreas give the normals); any other type that
// writes no value is refused.
std::vector<double> readBoundaryValues(const std::filesystem::path& file, const FoamMesh& mesh,
                                       const FoamField& internal, const std::vector<Vec3>& faceAreas);
// A surfaceScalarField (e.g. phi): the internal faces, then every non-empty patch's faces.
std::vector<double> readSurfaceField(const std::filesystem::path& file, const FoamMesh& mesh);

// The powder phase's viscosity model and coefficients as constant/transportProperties gives them
// to the solver (model name under "model", then rho and every <model>Coeffs number).
struct PowderTransport {
    std::string model;
    std::vector<std::pair<std::string, double>> values;
};
PowderTransport readPowderTransport(const std::filesystem::path& caseDir);

// Time directories of a case (numeric names), sorted by time; the names as written.
std::vector<std::string> timeDirectories(const std::filesystem::path& caseDir);

// The cell zones of a polyMesh directory (constant/polyMesh/cellZones), by name; none when the
// mesh has no such file.
std::vector<std::pair<std::string, std::vector<int32_t>>> readCellZones(const std::filesystem::path& polyMeshDir);

// The frozen-rotor zones of constant/MRFProperties (none without the file or with inactive zones):
// what turns the solver's absolute velocity into the flux it transports the powder with.
struct MrfZone {
    std::string name, cellZone;
    Vec3 origin{}, axis{};
    double omega = 0;  // rad/s
};
std::vector<MrfZone> readMrfZones(const std::filesystem::path& caseDir);

// The state a function object keeps at a written time (<time>/uniform/functionObjects/
// functionObjectProperties): the entries of its sub-dictionary `object`, each a number (one
// element) or a list of numbers. Anything else (words, nested dictionaries) is refused.
std::map<std::string, std::vector<double>> readFunctionObjectState(const std::filesystem::path& file,
                                                                   const std::string& object);

}  // namespace mixload::post
