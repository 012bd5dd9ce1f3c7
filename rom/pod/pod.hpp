// SPDX-License-Identifier: GPL-3.0-or-later
// Proper orthogonal decomposition by the method of snapshots, in the cell-volume-weighted inner
// product <u, v> = sum_c V_c u_c . v_c (the discrete L2 product of finite volumes), so that modes do
// not depend on how the mesh is graded.
//
// The snapshot matrix is never held whole: snapshots arrive in blocks (one snapshot file each), the
// N x N Gram matrix is built block pair by block pair (each block is read once per later block,
// two blocks in memory at a time), and the modes are summed block by block.
#pragma once
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Dense>

namespace mixload::rom {

struct PodOptions {
    int maxModes = 0;        // at most this many modes (0: no cap)
    double energy = 0.9999;  // keep the fewest modes that hold this share of the fluctuation energy
    bool subtractMean = true;
    // Coupled fields: the row where each field starts (e.g. {0, cells} for alpha then U). With
    // more than one, each field's weights are divided by its fluctuation energy, so that every
    // field carries the same share whatever its units.
    std::vector<Eigen::Index> fieldStarts;
};

struct PodBasis {
    Eigen::VectorXd weights;      // per row: the cell volume of the row's cell (over its field's energy if coupled)
    std::vector<double> fieldScales;  // per field: what its cell volumes were divided by (1 alone)
    Eigen::VectorXd mean;         // per row (zero when the mean is not subtracted)
    Eigen::MatrixXd modes;        // rows x K, orthonormal in the weighted product
    Eigen::VectorXd eigenvalues;  // all N, descending: the energy sum_j |x_j - mean|^2 per mode
    Eigen::MatrixXd coefficients; // N x K: the training snapshots' coordinates
    size_t snapshots = 0;
    double peakBytes = 0;         // the largest working set the algorithm held (blocks, Gram, modes)

    double totalEnergy() const { return eigenvalues.sum(); }
    // Share of the fluctuation energy the kept modes hold.
    double keptEnergy() const;
    // a = Phi^T W (u - mean).
    Eigen::VectorXd project(const Eigen::VectorXd& u) const;
    Eigen::VectorXd reconstruct(const Eigen::VectorXd& a) const { return mean + modes * a; }
    // max |Phi^T W Phi - I|: how orthonormal the modes are (round-off: about 1e-13).
    double orthonormalityError() const;
};

// blocks: how many; block(b): the columns of block b (rows x n_b, the same rows for all);
// weights: rows. Throws std::invalid_argument on empty input or mismatched rows.
PodBasis computePod(size_t blocks, const std::function<Eigen::MatrixXd(size_t)>& block,
                    const Eigen::VectorXd& weights, const PodOptions& options);

}  // namespace mixload::rom
