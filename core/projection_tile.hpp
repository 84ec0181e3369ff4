#pragma once
// The hot tile of project_lut (core/projection.hpp): T = P^T F_J (modes x w) for a block of w LUT columns,
// as dot products along the cells, at the widest vectors the CPU has (run-time dispatch,
// core/simd_target.hpp). Both P's columns and F's columns are contiguous along the cells, so neither is
// packed. Register tile: 3 modes x 8 LUT columns of 8-lane accumulators on AVX-512 (32 vector registers),
// 3 modes x 4 columns on narrower targets (16 registers); the cells go in chunks so that the chunk of P
// (modes x chunk) stays in L2 while each F column is read from memory once. A short last mode group repeats
// the last mode, columns beyond a multiple of the tile width take a one-column tile, and cells beyond a
// multiple of the vector width are added in the final reduction.
// Rounding: each entry is a sum over the cells taken in lanes, then the lanes summed pairwise; the order is
// fixed by the target (not by the thread count).
#include <Eigen/Core>
#include <vector>

namespace icobrdf {

// p: cells x modes (column-major); f: the first of w LUT columns of `cells` values, column stride ldf;
// t is resized to modes x w. `scratch` is reused between calls (one per thread).
void projection_tile(const Eigen::MatrixXd& p, const double* f, Eigen::Index ldf, Eigen::Index w, Eigen::MatrixXd& t,
                     std::vector<double>& scratch);

}  // namespace icobrdf
