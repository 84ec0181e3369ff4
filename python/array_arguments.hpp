#pragma once
// numpy arrays handed to the Python module `icobrdf`, as the library's types: directions as (n, 3) float64
// arrays of unit vectors (+z the normal, z >= 0, row-major once copied), an incident direction as 3 values,
// and evaluations at n direction pairs made chunk by chunk (eval_chunked). Shape errors are ArgumentError
// (ValueError in Python), naming the argument and the shape found.
#include <pybind11/eigen.h>
#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <algorithm>
#include <string>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf::python {

namespace py = pybind11;

// Any 2-D float64 array, without a copy when it is row-major already.
using DirArray = Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>;

// Directions from an (n, 3) array, copied into the library's row-major type; `what` names the argument.
RowMatrix3d directions(const DirArray& a, const char* what);

// The incident direction wi of 3 values.
Eigen::Vector3d incident_direction(const Eigen::Ref<const Eigen::VectorXd>& wi);

// Pairs per chunk when evaluating from numpy arrays: the directions are copied into reused row-major
// buffers of this many rows (6 MB each) instead of whole new copies, whose first touch cost a third of the
// evaluation at 10^6 pairs. Measured at 2^20 pairs, order 8, 2 threads: chunks of 2^16 reach 0.50 of the
// C++ rate (each call's threads get too little work), 2^18 0.94, one whole copy 0.65.
constexpr Eigen::Index kEvalChunk = Eigen::Index{1} << 18;

// fn(wi_chunk, wr_chunk) -> rows x cols values, applied chunk by chunk into one n x cols result, with the GIL
// released. ArgumentError unless wi and wr are (n, 3) with the same n.
template <class Fn>
Eigen::MatrixXd eval_chunked(const DirArray& wi, const DirArray& wr, Eigen::Index cols, Fn fn) {
  if (wi.cols() != 3 || wr.cols() != 3)
    throw ArgumentError(std::string(wi.cols() != 3 ? "wi" : "wr") + ": expected an (n, 3) array of unit vectors, found (" +
                        std::to_string(wi.cols() != 3 ? wi.rows() : wr.rows()) + ", " + std::to_string(wi.cols() != 3 ? wi.cols() : wr.cols()) + ")");
  if (wi.rows() != wr.rows())
    throw ArgumentError("eval: wi has " + std::to_string(wi.rows()) + " rows, wr has " + std::to_string(wr.rows()));
  const Eigen::Index n = wi.rows();
  Eigen::MatrixXd out(n, cols);
  py::gil_scoped_release release;
  RowMatrix3d a, b;
  for (Eigen::Index r0 = 0; r0 < n; r0 += kEvalChunk) {
    const Eigen::Index m = std::min(kEvalChunk, n - r0);
    a = wi.middleRows(r0, m);
    b = wr.middleRows(r0, m);
    out.middleRows(r0, m) = fn(a, b);
  }
  return out;
}

}  // namespace icobrdf::python
