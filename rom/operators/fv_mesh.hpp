// SPDX-License-Identifier: GPL-3.0-or-later
// The finite-volume mesh as OpenFOAM's operators see it, rebuilt from a snapshot file's /mesh: cells,
// internal faces, and the faces of the non-empty patches (an empty patch, the third direction of a
// 2D case, takes no part). Geometry and the coefficients OpenFOAM derives from it (linear
// interpolation weights, delta coefficients, non-orthogonal correction vectors) follow
// surfaceInterpolation in OpenFOAM v1912, so that operators agree with fvc to round-off.
#pragma once
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "store/snapshot_file.hpp"

namespace mixload::rom {

using Vectors = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// A vector field's snapshot column (the components of a cell together) as rows of vectors.
inline Vectors asVectors(const Eigen::VectorXd& v) { return Eigen::Map<const Vectors>(v.data(), v.size() / 3, 3); }

struct FvMesh {
    Eigen::Index cells = 0, internalFaces = 0, boundaryFaces = 0;  // boundaryFaces: non-empty patches
    // Faces in operator order: internal faces, then the non-empty patches' faces in patch order.
    std::vector<int32_t> owner, neighbour;  // neighbour: internal faces only
    Vectors Sf, Cf, C;                      // face area vectors, face centres, cell centres
    Eigen::VectorXd V, magSf;
    Eigen::VectorXd weights;                // internal faces: owner's share of linear interpolation
    Eigen::VectorXd deltaCoeffs;            // all faces: 1 / |n . d| (boundary), 1/max(n.d, 0.05|d|) (internal)
    Vectors corrVecs;                       // internal faces: n - d * deltaCoeffs
    bool orthogonal = false;                // correction vectors at round-off: Laplacians skip the correction
    struct Patch {
        std::string name, type;
        Eigen::Index start = 0, size = 0;   // in operator order
    };
    std::vector<Patch> patches;             // non-empty patches

    Eigen::Index faces() const { return internalFaces + boundaryFaces; }
    // The non-empty patch of that name (InputError naming it when there is none).
    const Patch& patch(const std::string& name) const;
    static FvMesh fromCase(const store::CaseFile& f);
};

}  // namespace mixload::rom
