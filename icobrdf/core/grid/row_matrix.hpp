#pragma once
// Row-major matrices of 3 columns, one row per item: RowMatrix3d for directions and points (unit vectors with
// +z the normal, or positions; docs/conventions.md), RowMatrix3i for index triples (the (n, m, l) of IBSSS modes).
// Row-major: the 3 values of a row are contiguous.
#include <Eigen/Core>

namespace icobrdf {

using RowMatrix3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowMatrix3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

}  // namespace icobrdf
