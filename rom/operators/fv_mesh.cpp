// SPDX-License-Identifier: GPL-3.0-or-later
#include "rom/operators/fv_mesh.hpp"

#include <algorithm>
#include <cmath>

#include "common/input_error.hpp"

namespace mixload::rom {

namespace {
Vectors rows3(const std::vector<double>& v, const std::vector<Eigen::Index>& pick) {
    Vectors out(static_cast<Eigen::Index>(pick.size()), 3);
    for (size_t i = 0; i < pick.size(); ++i)
        for (int k = 0; k < 3; ++k) out(static_cast<Eigen::Index>(i), k) = v[static_cast<size_t>(pick[i]) * 3 + k];
    return out;
}
}  // namespace

FvMesh FvMesh::fromCase(const store::CaseFile& f) {
    FvMesh m;
    const auto owner = f.meshInts("owner");
    m.neighbour = f.meshInts("neighbour");
    m.cells = static_cast<Eigen::Index>(f.cells());
    m.internalFaces = static_cast<Eigen::Index>(m.neighbour.size());
    std::vector<Eigen::Index> pick;
    for (Eigen::Index i = 0; i < m.internalFaces; ++i) pick.push_back(i);
    for (const auto& p : f.patches()) {
        if (p.type == "empty") continue;
        m.patches.push_back({p.name, p.type, static_cast<Eigen::Index>(pick.size()), static_cast<Eigen::Index>(p.size)});
        for (long long i = 0; i < p.size; ++i) pick.push_back(static_cast<Eigen::Index>(p.start + i));
    }
    m.boundaryFaces = static_cast<Eigen::Index>(pick.size()) - m.internalFaces;
    for (auto i : pick) m.owner.push_back(owner.at(static_cast<size_t>(i)));
    m.Sf = rows3(f.meshDoubles("face_areas"), pick);
    m.Cf = rows3(f.meshDoubles("face_centres"), pick);
    std::vector<Eigen::Index> all(static_cast<size_t>(m.cells));
    for (Eigen::Index c = 0; c < m.cells; ++c) all[static_cast<size_t>(c)] = c;
    m.C = rows3(f.meshDoubles("cell_centres"), all);
    m.V = f.cellVolumes();
    m.magSf = m.Sf.rowwise().norm();

    const Eigen::Index nF = m.faces();
    m.weights.resize(m.internalFaces);
    m.deltaCoeffs.resize(nF);
    m.corrVecs.resize(m.internalFaces, 3);
    for (Eigen::Index i = 0; i < nF; ++i) {
        const auto o = m.owner[static_cast<size_t>(i)];
        const Eigen::RowVector3d n = m.Sf.row(i) / m.magSf[i];
        if (i < m.internalFaces) {
            const auto nb = m.neighbour[static_cast<size_t>(i)];
            // surfaceInterpolation::makeWeights
            const double own = std::abs(m.Sf.row(i).dot(m.Cf.row(i) - m.C.row(o)));
            const double nei = std::abs(m.Sf.row(i).dot(m.C.row(nb) - m.Cf.row(i)));
            m.weights[i] = nei / (own + nei);
            // makeNonOrthDeltaCoeffs and makeNonOrthCorrectionVectors
            const Eigen::RowVector3d d = m.C.row(nb) - m.C.row(o);
            m.deltaCoeffs[i] = 1.0 / std::max(n.dot(d), 0.05 * d.norm());
            m.corrVecs.row(i) = n - d * m.deltaCoeffs[i];
        } else {
            // fvPatch::delta() of a non-coupled patch is normal to it: n (n . (Cf - C)).
            const double dn = n.dot(m.Cf.row(i) - m.C.row(o));
            m.deltaCoeffs[i] = 1.0 / std::max(dn, 0.05 * std::abs(dn));
        }
    }
    // Round-off in n - d deltaCoeffs (about 1e-16) is not non-orthogonality; 1e-12 leaves the
    // correction out only where it cannot reach the operators' verified 1e-10.
    m.orthogonal = m.internalFaces == 0 || m.corrVecs.cwiseAbs().maxCoeff() < 1e-12;
    return m;
}

const FvMesh::Patch& FvMesh::patch(const std::string& name) const {
    for (const auto& p : patches)
        if (p.name == name) return p;
    throw InputError("patch", name, "a patch of the mesh");
}

}  // namespace mixload::rom
