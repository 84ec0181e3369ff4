#pragma once
// What the streaming projection (icobrdf/core/projection/streaming_projection.hpp) and its row-split form
// (icobrdf/core/projection/row_split_projection.hpp) share: the block size of incident rows, the tolerances of
// their symmetry checks, and the work symmetry and reciprocity let them save. Both include this header, so the
// row-split projection does not include the streaming one (the streaming projection takes a row split's exchange).
#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/projection/lut.hpp"

namespace icobrdf {

// Incident cells per block of the streaming projection: each thread holds kStreamingBlockRows x cells doubles
// per channel of LUT rows (2.6 MB at level 5; icobrdf/pipeline/resource_estimate.hpp counts them).
inline constexpr int kStreamingBlockRows = 32;
// Finished blocks whose partial sums (modes x modes per channel and part) may wait for the blocks before
// them to be added (icobrdf/core/support/in_order_sums.hpp; here and in the row-split projection): enough that a
// thread finishing a cheap block goes on while the other finishes a costly one
// (icobrdf/pipeline/resource_estimate.hpp counts them).
inline constexpr int kStreamingBlocksAhead = 4;

// Tolerance of the check that P is D2-equivariant (the sampling's own check is sampling_is_d2_symmetric,
// icobrdf/core/basis/grid_symmetry.hpp): a grid built symmetric matches to rounding, 1e-12 leaves room for a few ulps of
// the mesh construction and of G^-1 while rejecting any grid that is symmetric only up to discretization.
inline constexpr double kStreamingSymmetryTol = 1e-12;
// Solid angles of the sampling grid against the projection grid's, relative to the largest: the two are
// built from the same cells (build_fitting_grid with either cubature), so they agree to the rounding of
// summing cubature weights; any real difference in cells is far larger.
inline constexpr double kSameCellsRelTol = 1e-12;

// The work a streaming projection may save, shared by streaming_projection and row_split_projection:
// `d2` one incident row per D2 orbit (an isotropic model on grids with the same symmetric sampling; the
// caller still checks that its rows of P are equivariant), `reciprocal` one triangle of the symmetric f LUT
// (f form, or g form with centre sampling). ArgumentError when the sampling grid's cells differ from g's,
// or for a delta part without the g form.
struct StreamingShortcuts {
  bool d2 = false, reciprocal = false;
};
StreamingShortcuts streaming_shortcuts(const BrdfModel& model, const Grid& g, const Grid& sg, bool cosine, LutSampling sampling);

}  // namespace icobrdf
