#pragma once
// numpy arrays handed to the Python module `icobrdf`, as the library's types: directions as float64 arrays of
// unit vectors (+z the normal, row-major once copied), either (n, 3) or one direction as a 1-D array of 3
// values; an incident direction as 3 values; and evaluations at n direction pairs made chunk by chunk
// (eval_chunked), where one of wi, wr may be a single direction paired with every row of the other. Every
// direction is checked to be a unit vector (icobrdf/io/unit_directions.hpp). Shape and length errors are
// ArgumentError (ValueError in Python), naming the argument, the row or shape found and what was expected.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <algorithm>
#include <string>
#include <utility>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf::python {

namespace py = pybind11;

// Directions as passed: any float array (other dtypes are converted to float64), (n, 3) or (3,); no copy when
// it is a C-contiguous float64 array already.
using DirArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// The rows of `a` viewed as n x 3 (a 1-D array of 3 values: one row), checked to be unit vectors; `what` names
// the argument. The view lives as long as `a`.
Eigen::Map<const RowMatrix3d> direction_rows(const DirArray& a, const char* what);

// The same, copied into the library's row-major type.
RowMatrix3d directions(const DirArray& a, const char* what);

// ArgumentError (ValueError) naming `what`, the row and the column of the first value that is NaN or infinite:
// the array arguments of numbers (LUTs, coefficient matrices) are checked before any work, as the CLI's readers
// check files.
void require_finite_argument(const Eigen::Ref<const Eigen::MatrixXd>& a, const char* what);

// The incident direction wi of 3 values.
Eigen::Vector3d incident_direction(const Eigen::Ref<const Eigen::VectorXd>& wi);

// Pairs (wi[r], wr[r]): wi and wr of the same n rows, or one of them a single direction given as a 1-D array
// (shape (3,)) paired with every row of the other. Returns n; ArgumentError otherwise (an (1, 3) array is n = 1).
Eigen::Index pair_count(const DirArray& wi, const DirArray& wr);

// wi and wr copied as n x 3 matrices of pairs (a single direction repeated n times), n = pair_count.
std::pair<RowMatrix3d, RowMatrix3d> direction_pairs(const DirArray& wi, const DirArray& wr);

// Rows r0 .. r0 + m of `w` as pairs see them: those rows, or the single row repeated m times.
void pair_rows(const Eigen::Map<const RowMatrix3d>& w, Eigen::Index r0, Eigen::Index m, RowMatrix3d& out);

// Pairs per chunk when evaluating from numpy arrays: the directions are copied into reused row-major
// buffers of this many rows (6 MB each) instead of whole new copies, whose first touch cost a third of the
// evaluation at 10^6 pairs. Measured at 2^20 pairs, order 8, 2 threads: chunks of 2^16 reach 0.50 of the
// C++ rate (each call's threads get too little work), 2^18 0.94, one whole copy 0.65.
constexpr Eigen::Index kEvalChunk = Eigen::Index{1} << 18;

// fn(wi_chunk, wr_chunk) -> rows x cols values, applied chunk by chunk into one n x cols result, with the GIL
// released. ArgumentError unless wi and wr are directions (n, 3) of the same n, or one of them a single one.
template <class Fn>
Eigen::MatrixXd eval_chunked(const DirArray& wi, const DirArray& wr, Eigen::Index cols, Fn fn) {
  const auto a_all = direction_rows(wi, "wi");
  const auto b_all = direction_rows(wr, "wr");
  const Eigen::Index n = pair_count(wi, wr);
  Eigen::MatrixXd out(n, cols);
  py::gil_scoped_release release;
  RowMatrix3d a, b;
  for (Eigen::Index r0 = 0; r0 < n; r0 += kEvalChunk) {
    const Eigen::Index m = std::min(kEvalChunk, n - r0);
    pair_rows(a_all, r0, m, a);
    pair_rows(b_all, r0, m, b);
    out.middleRows(r0, m) = fn(a, b);
  }
  return out;
}

}  // namespace icobrdf::python
