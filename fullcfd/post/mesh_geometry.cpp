// SPDX-License-Identifier: GPL-3.0-or-later
#include "post/mesh_geometry.hpp"

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "common/hash.hpp"

namespace mixload::post {

namespace {
Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double mag(const Vec3& a) { return std::sqrt(dot(a, a)); }
constexpr double kVSmall = 1e-300, kRootVSmall = 1e-150;
}  // namespace

MeshGeometry meshGeometry(const FoamMesh& mesh) { return meshGeometry(mesh, mesh.points); }

MeshGeometry meshGeometry(const FoamMesh& mesh, const std::vector<Vec3>& pts) {
    if (pts.size() != mesh.points.size())
        throw std::runtime_error("moving mesh: " + std::to_string(pts.size()) + " points for a mesh of " +
                                 std::to_string(mesh.points.size()));
    const size_t nF = mesh.nFaces(), nC = static_cast<size_t>(mesh.nCells);
    MeshGeometry g;
    g.faceCentres.resize(nF);
    g.faceAreas.resize(nF);
    for (size_t f = 0; f < nF; ++f) {
        const int32_t b = mesh.faceOffsets[f], n = mesh.faceOffsets[f + 1] - b;
        const auto p = [&](int32_t i) -> const Vec3& { return pts[mesh.facePoints[b + i % n]]; };
        if (n == 3) {
            g.faceCentres[f] = (1.0 / 3.0) * (p(0) + p(1) + p(2));
            g.faceAreas[f] = 0.5 * cross(p(1) - p(0), p(2) - p(0));
            continue;
        }
        Vec3 mid{};
        for (int32_t i = 0; i < n; ++i) mid = mid + p(i);
        mid = (1.0 / n) * mid;
        Vec3 sumN{}, sumAc{};
        double sumA = 0;
        for (int32_t i = 0; i < n; ++i) {
            const Vec3 c = p(i) + p(i + 1) + mid;
            const Vec3 nrm = cross(p(i + 1) - p(i), mid - p(i));
            const double a = mag(nrm);
            sumN = sumN + nrm;
            sumA += a;
            sumAc = sumAc + a * c;
        }
        if (sumA < kRootVSmall) {
            g.faceCentres[f] = mid;
            g.faceAreas[f] = {};
        } else {
            g.faceCentres[f] = (1.0 / (3.0 * sumA)) * sumAc;
            g.faceAreas[f] = 0.5 * sumN;
        }
    }

    // First guess of each cell centre: the mean of its face centres.
    std::vector<Vec3> est(nC);
    std::vector<int> count(nC, 0);
    const auto addFace = [&](int32_t c, size_t f) {
        est[c] = est[c] + g.faceCentres[f];
        ++count[c];
    };
    for (size_t f = 0; f < nF; ++f) addFace(mesh.owner[f], f);
    for (size_t f = 0; f < mesh.neighbour.size(); ++f) addFace(mesh.neighbour[f], f);
    for (size_t c = 0; c < nC; ++c) est[c] = (1.0 / std::max(count[c], 1)) * est[c];

    g.cellCentres.assign(nC, Vec3{});
    g.cellVolumes.assign(nC, 0.0);
    const auto pyramid = [&](int32_t c, size_t f, double sign) {
        const double v3 = std::max(sign * dot(g.faceAreas[f], g.faceCentres[f] - est[c]), kVSmall);
        g.cellCentres[c] = g.cellCentres[c] + v3 * (0.75 * g.faceCentres[f] + 0.25 * est[c]);
        g.cellVolumes[c] += v3;
    };
    for (size_t f = 0; f < nF; ++f) pyramid(mesh.owner[f], f, 1.0);
    for (size_t f = 0; f < mesh.neighbour.size(); ++f) pyramid(mesh.neighbour[f], f, -1.0);
    for (size_t c = 0; c < nC; ++c) {
        g.cellCentres[c] = std::abs(g.cellVolumes[c]) > kVSmall
                               ? (1.0 / g.cellVolumes[c]) * g.cellCentres[c]
                               : est[c];
        g.cellVolumes[c] /= 3.0;
    }
    return g;
}

}  // namespace mixload::post

namespace mixload::post {

std::string meshChecksum(const FoamMesh& mesh) {
    std::string bytes;
    const auto put = [&](const void* p, size_t n) { bytes.append(static_cast<const char*>(p), n); };
    put(&mesh.nCells, sizeof mesh.nCells);
    for (const auto& p : mesh.points) put(p.data(), sizeof(double) * 3);
    for (const auto* v : {&mesh.faceOffsets, &mesh.facePoints, &mesh.owner, &mesh.neighbour}) {
        const size_t n = v->size();
        put(&n, sizeof n);
        put(v->data(), sizeof(int32_t) * n);
    }
    for (const auto& p : mesh.patches) bytes += p.name + ' ' + p.type + ' ' + std::to_string(p.start) + ' ' + std::to_string(p.size) + '\n';
    return stableHash(bytes);
}

}  // namespace mixload::post
