#pragma once
// Peak memory of a request, estimated from its sizes before anything is allocated, and the refusal of a
// request that the machine cannot hold (icobrdf/core/support/memory_budget.hpp), naming the largest level or order that fits.
//
// Sizes: C = cells of the level (equal_area_cells, icobrdf/io/spectrum_file.hpp), M = hemisphere functions of order N
// (hemisphere_basis_count, icobrdf/core/basis/hemisphere_basis.hpp),
// ch = channels, T = threads. The estimates count the arrays that grow with C and M, in doubles:
//   grid                C x kGridBytesPerCell (directions, maps, a degree-9 cubature of ~37 points per cell)
//   projection context  3 C M (B, P and the weighted basis alive while P is made) + (kGramPartialSums + 3) M^2
//   streaming fit       + 4 C M ([P Q]: P with its cosine-weighted copy side by side, and [P Q] packed for the
//                       projection tile) + T (kStreamingBlockRows C ch) LUT rows
//                       + (2 (T + A) + 4) ch M^2 partial and final sums, both parts of a cosine fit, with up to
//                       A = kStreamingBlocksAhead finished blocks waiting to be added in order
//   LUT                 ch C^2 (float64) + its row-major copy for writing (half of it for float32)
// They are checked against the peak resident memory measured at several sizes in
// tests/pipeline/test_resource_estimate.cpp: within kEstimateFactor of it, and never below it by more than
// the process's fixed footprint (libraries, mesh), which the estimates leave out.
#include <string>

namespace icobrdf {

// Bytes per cell of a grid that do not depend on the order: representative directions, solid angles, the
// neighbour and symmetry maps, and the cubature (points and weights; 37 points per cell at degree 9).
inline constexpr double kGridBytesPerCell = 1600.0;

// Peak bytes of fitting an analytic model by streaming projection at (level, order): no LUT is materialized.
// With parts > 1: per process of a fit whose operators are split by rows over `parts` processes
// (icobrdf/core/projection/row_split_projection.hpp): 4 (C / R) M for P, the visiting block and the exchange's copies,
// T kStreamingBlockRows 2 (C / R) ch LUT rows, and the M^2 terms; the grid stays whole.
double model_fit_bytes(int level, int order, int channels, int threads, int parts = 1);
// Peak bytes of sampling a LUT of a model at `level` and projecting it to `order` (the lut command), and of
// smoothing or fitting a stored one: the LUT and its copy for writing dominate from level 4 on.
double lut_bytes(int level, int order, int channels, bool float32, int threads);

// Peak bytes of `icobrdf sample` at `level`: the grid, the incident distribution (cell centres, or with
// cell_average the degree-9 cubature points: ~37 per cell, each with its direction, w_i and f per channel)
// and one block of draws (icobrdf/io/sample_draws.hpp); the number of draws does not enter.
double sampling_bytes(int level, bool cell_average, int channels);
// ResourceError when sampling_bytes exceeds available_memory(), naming the largest level that fits.
void require_sampling_memory(int level, bool cell_average, int channels, const std::string& what);

// Peak bytes of `icobrdf bench project` at (level, order): one dense C x C LUT of random values, the grid, the
// projection's context and the C x M products of the OpenBLAS paths it is timed against.
double projection_bench_bytes(int level, int order);
// ResourceError when projection_bench_bytes exceeds available_memory(), naming the largest level that fits.
void require_projection_bench_memory(int level, int order);

// The pieces, for entry points that make one at a time (the Python module): the grid of a level while it is
// built, a discrete basis of `order` on `cells` cells (B, P and the weighted basis), and a float64 LUT.
double grid_bytes(int level);
double basis_bytes(double cells, int order);
double lut_table_bytes(double cells, int channels);

// The threads OpenMP will use (omp_get_max_threads), for the per-thread terms.
int estimate_threads();

// ResourceError (icobrdf/core/support/error.hpp) when a model fit at (level, order) needs more than available_memory(),
// naming the largest order that fits at this level.
void require_model_fit_memory(int level, int order, int channels, const std::string& what, int parts = 1);
// The same for a LUT of `level` (sampled, stored and projected to `order`).
void require_lut_memory(int level, int order, int channels, bool float32, const std::string& what);

// The largest order <= order_max whose model fit at `level` fits in available_memory() (-1: none).
int largest_order_in_memory(int level, int order_max, int channels);

}  // namespace icobrdf
