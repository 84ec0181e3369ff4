#pragma once
// f of a stored material (icobrdf/io/spectrum_file.hpp MaterialRecord) at direction pairs, for every representation:
//   modes       sum_ab C_ab K_a(w_i) K_b(w_r), divided by cos(theta_i) when the spectrum is of g = f cos
//   half-angle  the lobe (icobrdf/core/models/half_angle_factors.hpp), C being zero
//   hybrid      modes + lobe
// A material with a lobe returns max(0, modes + lobe): a BRDF is never negative, and the lobe's linear
// interpolation across the horizon boundary of its valid region (near double grazing) can undershoot; the
// clamp is symmetric in w_i and w_r, so reciprocity is kept. Modes alone are returned as they are (their
// exact reconstruction is what the LUT operators reproduce).
// wi, wr: rows x 3 unit vectors; returns rows x channels [1/sr].
#include <Eigen/Core>

#include <optional>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/models/half_angle_factors.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"

namespace icobrdf {

Eigen::MatrixXd evaluate_material(const Spectrum& modes, const std::optional<HalfAngleFactors>& lobe, const RowMatrix3d& wi,
                                  const RowMatrix3d& wr);

// The same with the modes' values at the pairs already known (rows x channels): max(0, modes + lobe).
Eigen::MatrixXd add_lobe(const Eigen::MatrixXd& modes_values, const HalfAngleFactors& lobe, const RowMatrix3d& wi,
                         const RowMatrix3d& wr);

}  // namespace icobrdf
