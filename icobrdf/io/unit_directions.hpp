#pragma once
// Directions handed in by a caller as numbers (the Python module's arrays, samples given as arrays): unit
// vectors, +z the normal, checked with one rule and one message. A vector that is not of unit length (a
// direction never normalized, [0, 0, 2]) is refused rather than evaluated as if it were one.
#include <Eigen/Core>

#include <string>

#include "icobrdf/core/grid/row_matrix.hpp"

namespace icobrdf {

// | |w| - 1 | accepted: a double-precision normalization leaves a few 1e-16 (the sampler's and the cell
// locator's 1e-10 likewise), while a vector never normalized is off by far more. A vector normalized in
// float32 (|w| - 1 ~ 1e-7) is refused too: normalize in float64.
inline constexpr double kUnitDirectionTolerance = 1e-10;

// ArgumentError unless every row of `w` is finite and of unit length within kUnitDirectionTolerance and, when
// `above_horizon`, has z >= -kHorizonSlack (icobrdf/core/basis/horizon.hpp). The message names `what`, the row, the
// vector found and what was expected, e.g. "wi: row 0 (0, 0, 2) has length 2, expected a unit vector (length 1
// within 1e-10)".
void require_unit_directions(const Eigen::Ref<const RowMatrix3d>& w, const std::string& what, bool above_horizon);

}  // namespace icobrdf
