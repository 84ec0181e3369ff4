#pragma once
// The hot tile of project_lut (icobrdf/core/projection/projection.hpp): T = P^T F_J (modes x w) for a block of w LUT columns,
// as dot products along the cells, at the widest vectors the CPU has (run-time dispatch,
// icobrdf/core/support/simd_target.hpp). P is packed once per projection (pack_projection: per group of M modes, the M
// modes' vectors of consecutive cells side by side); F's columns are read in place. Register tile: M = 5
// modes x 5 LUT columns of 8-lane accumulators on AVX-512 (32 vector registers), M = 3 modes x 4 columns on
// narrower targets (16 registers). Loop order, outer to inner: blocks of cells (the block of packed P, at
// most 384 KiB or one chunk, 1024 cells at order 8, stays in L2; each F column is read in runs of 8 KB
// there, long enough for the hardware prefetcher), tiles of columns, chunks of 256 cells (the tile's chunk
// of F, 10 KB on AVX-512, stays in L1 for the mode groups after the first; the next chunk's F lines are
// prefetched meanwhile, one line per step of the groups' loops), groups of modes, cells.
// A short last mode group has a tile of its own size, columns beyond a multiple of the tile width take a
// one-column tile, and cells beyond a multiple of the vector width are added in the final reduction.
// Rounding: each entry is a sum over the cells taken in lanes, then the lanes summed pairwise; the order is
// fixed by the target (not by the thread count).
#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace icobrdf {

constexpr std::size_t kPackAlignBytes = 64;  // packed buffers start on a cache line (the widest vector)

// P (cells x modes) packed for the tile of the SIMD target dispatched when it was packed.
struct PackedProjection {
  std::vector<double> storage;  // the packed values start at data(), 64-byte aligned
  std::size_t offset = 0;       // doubles from storage's start to data()
  Eigen::Index cells = 0, modes = 0, lanes = 0;
  Eigen::Index group_modes = 0;  // modes per register tile of that target (the last group may have fewer)
  const double* data() const { return storage.data() + offset; }
};

PackedProjection pack_projection(const Eigen::MatrixXd& p);

// t = P(K, :)^T F(K, J) over the cells K = [first_cell, end_cell) (end_cell < 0: all cells). p: the P that
// `packed` holds, cells x modes; f: the first of w LUT columns of `cells` values (its row 0), column stride
// ldf; t is resized to modes x w. `scratch` is reused between calls (one per thread). ArgumentError when
// `packed` was packed for another tile shape (vector width, modes per group) than the one dispatched now, or when first_cell is not a
// multiple of the packed lanes, or end_cell neither such a multiple nor `cells`.
void projection_tile(const PackedProjection& packed, const Eigen::MatrixXd& p, const double* f, Eigen::Index ldf, Eigen::Index w,
                     Eigen::MatrixXd& t, std::vector<double>& scratch, Eigen::Index first_cell = 0, Eigen::Index end_cell = -1);

}  // namespace icobrdf
