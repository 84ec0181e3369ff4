#pragma once
// Spectrum of an analytic model without materializing its LUT: C = P^T F P accumulated over blocks of
// incident cells, F's rows sampled on the fly (icobrdf/core/projection/lut.hpp). Memory O(cells x modes + block x cells);
// the result equals project_lut(P, build_lut(...)) up to the summation order.
// Work saved by symmetry: an isotropic model on a D2-symmetric grid samples one incident cell per orbit
// (a quarter of F); a Helmholtz-reciprocal model (BrdfModel::is_reciprocal) samples one triangle of the
// symmetric f LUT (half of F; an eighth with D2), in f form with either sampling and in g form with centre
// sampling (a cell-averaged g LUT is not diag(cos) times a symmetric matrix, so it takes the full path).
//
// Shares (StreamingShare): the blocks of incident rows can be split over several processes, each projecting
// its own blocks and `reduce` summing their matrices (icobrdf/cluster/distributed_projection.hpp does it
// over MPI; core knows nothing of MPI).
#include <Eigen/Core>

#include <functional>
#include <memory>
#include <vector>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/projection/row_split_projection.hpp"
#include "icobrdf/core/projection/streaming_shortcuts.hpp"

namespace icobrdf {

// One process's share of the blocks of incident rows (blocks of kStreamingBlockRows sampled rows, numbered
// in the order of the rows: one per D2 orbit with symmetry, in ascending cell order). The share projects the
// blocks b with b % parts == part: interleaved, because the blocks of the reciprocal triangle grow with b
// (block b samples a prefix of the columns, up to its rows' orbits), so contiguous halves would give the
// last share most of the work while every interleaved share gets the same mix (costs within one block's).
// `reduce` receives the share's matrices (one M x M per channel, symmetry already applied, delta parts not
// yet added) and must replace them by the sum over all `parts` shares, in an order that does not depend on
// timing (then the result is the same bits for a fixed number of parts); it is called once per projection,
// from the calling thread, after the share's blocks are done. Delta parts are added after it, once.
// `every` > 1 (benchmarks only: `icobrdf bench streaming --every K`) keeps only the blocks b with
// b % every == 0 and shares those: the work of a projection too long to run whole, in the same mix, for
// timing (about K times the blocks' part of the time) and for the memory of every array at full size; the
// matrices are then not C.
struct StreamingShare {
  int part = 0;
  int parts = 1;
  int every = 1;
  std::function<void(std::vector<Eigen::MatrixXd>&)> reduce;
  // Optional: split the operators by rows over the processes instead (icobrdf/core/projection/row_split_projection.hpp):
  // a fit's context then holds this process's rows of P only, and its projection runs the ring through this
  // exchange. part, parts and reduce are then not used by the fit; every is (row_split_projection's).
  std::shared_ptr<RowSplitExchange> rows;
  // Optional: a sum like `reduce` for fits that are not projections and split their own work over the
  // processes (fits of scattered samples: icobrdf/core/fit/sample_fit.hpp SampleFitSplit, with part and parts);
  // it may be called any number of times, the same on every process.
  std::function<void(std::vector<Eigen::MatrixXd>&)> sample_sum;
};


// One M x M coefficient matrix per model channel. Delta parts are added exactly in g form.
// `sampling_grid`, when given, supplies the cubature used for the cell averages of the LUT rows: the same
// cells as `grid` (same count and solid angles) with a cheaper rule, since each LUT entry averages over the
// product of two cells' rules (cost grows with the square of the points per cell).
std::vector<Eigen::MatrixXd> streaming_projection(const BrdfModel& model, const Grid& grid, const ProjectionOperator& proj,
                                                  bool cosine, LutSampling sampling = LutSampling::CellAverage,
                                                  const Grid* sampling_grid = nullptr, const StreamingShare* share = nullptr);

// P^T F P of the g LUT of one delta part alone (F_ir = weight [r = image(i)] / Omega_r), in O(cells x modes):
// no LUT and no sampling. ArgumentError for a mirror part on a grid without the rotation-by-pi map.
Eigen::MatrixXd delta_projection(const DeltaPart& part, const Grid& grid, const ProjectionOperator& proj);

}  // namespace icobrdf
