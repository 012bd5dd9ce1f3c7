// SPDX-License-Identifier: GPL-3.0-or-later
// The collapse's runout and height from a powder-fraction field, defined exactly as the solver's
// collapseMonitor defines them (fullcfd/monitors): the deposit profile h(x) in bins one cell wide,
// the front at the right edge of the last bin holding at least half a cell of powder plus the
// filled share of the next, the height the profile's maximum. A reduced model's L* and H* are then
// comparable to the full run's digit for digit.
#pragma once

#include "rom/operators/fv_mesh.hpp"
#include "store/snapshot_file.hpp"

namespace mixload::rom {

struct CollapseShape {
    double length = 0, height = 0;      // the initial column, Li and Hi [m]
    double binWidth = 0, depth = 0;     // one cell; the 2D slab's thickness [m]
    int bins = 0;

    // From a collapse snapshot file's params and mesh; InputError for another scene.
    static CollapseShape fromCase(const store::CaseFile& f);
    Eigen::VectorXd profile(const FvMesh& m, const Eigen::VectorXd& alpha) const;
    double front(const Eigen::VectorXd& profile) const;
    double runoutStar(const FvMesh& m, const Eigen::VectorXd& alpha) const;  // (L - Li) / Li
    double heightStar(const FvMesh& m, const Eigen::VectorXd& alpha) const;  // max h / Hi
    // The column at t = 0 as the case sets it up: each cell's overlap with [0, Li] x [0, Hi].
    Eigen::VectorXd initialAlpha(const FvMesh& m) const;
};

// The lithostatic pressure: in every vertical column of cells, the weight of what lies above each
// cell centre. Used for the mu(I) law where a reduced model has projected the pressure away; its
// error against the solver's pressure is measured (rom/galerkin/collapse_check). Needs a mesh whose cells
// stand in columns (the collapse's blockMesh grid); throws InputError otherwise.
class ColumnPressure {
  public:
    ColumnPressure(const FvMesh& m, double gravity);
    Eigen::VectorXd operator()(const Eigen::VectorXd& rho) const;

  private:
    std::vector<std::vector<Eigen::Index>> columns_;  // each top down
    Eigen::VectorXd halfHeight_;                      // per cell: half its height
    double g_ = 0;
};

}  // namespace mixload::rom
