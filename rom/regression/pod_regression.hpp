// SPDX-License-Identifier: GPL-3.0-or-later
// POD regression: a field as a function of a few inputs, from the fields of runs at known inputs.
// The fields' POD (mean subtracted, cell-volume weights) gives K modes; one kriging model
// (surrogates/kriging) per mode maps the inputs, scaled to the training box, to the mode's
// coefficient; a prediction is the mean plus the predicted coefficients times the modes. No
// equations are solved: it is as good as the runs span the inputs and the modes span the fields.
#pragma once

#include <vector>

#include <Eigen/Dense>

#include "kriging/kriging.hpp"
#include "kriging/unit_box.hpp"
#include "rom/pod/pod.hpp"

namespace mixload::rom {

class PodRegression {
  public:
    // X: runs x inputs; fields: rows x runs; weights: rows (cell volumes). modes 0: by energy.
    static PodRegression fit(const Eigen::MatrixXd& X, const Eigen::MatrixXd& fields, const Eigen::VectorXd& weights,
                             int modes, double energy = 0.9999);
    Eigen::VectorXd predict(const Eigen::VectorXd& x) const;
    int modes() const { return static_cast<int>(basis_.modes.cols()); }
    const PodBasis& basis() const { return basis_; }

  private:
    PodBasis basis_;
    std::vector<surrogates::Kriging> coefficient_;
    surrogates::UnitBox box_;
};

}  // namespace mixload::rom
