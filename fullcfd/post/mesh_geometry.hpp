// SPDX-License-Identifier: GPL-3.0-or-later
// Face and cell geometry of a polyMesh computed as OpenFOAM computes it (face triangle fans about
// the point average, cell pyramids about the face-centre average), so snapshots and the reduced
// models see the same centres and volumes the solver integrated with.
#pragma once
#include <string>
#include <vector>

#include "post/foam_files.hpp"

namespace mixload::post {

struct MeshGeometry {
    std::vector<Vec3> faceCentres, faceAreas;  // area vectors point from owner to neighbour
    std::vector<Vec3> cellCentres;
    std::vector<double> cellVolumes;
};

MeshGeometry meshGeometry(const FoamMesh& mesh);
// Same topology, other points (a moving mesh).
MeshGeometry meshGeometry(const FoamMesh& mesh, const std::vector<Vec3>& points);

// A checksum of a mesh's points (their bits), faces, owners, neighbours and patches: two meshes with
// the same checksum are the same mesh, cell for cell.
std::string meshChecksum(const FoamMesh& mesh);

}  // namespace mixload::post
