#pragma once
// Spectrum of an analytic model without materializing its LUT: C = P^T F P accumulated over blocks of
// incident cells, F's rows sampled on the fly (icobrdf/core/lut.hpp). Memory O(cells x modes + block x cells);
// the result equals project_lut(P, build_lut(...)) up to the summation order.
// Work saved by symmetry: an isotropic model on a D2-symmetric grid samples one incident cell per orbit
// (a quarter of F); a Helmholtz-reciprocal model (BrdfModel::is_reciprocal) samples one triangle of the
// symmetric f LUT (half of F; an eighth with D2), in f form with either sampling and in g form with centre
// sampling (a cell-averaged g LUT is not diag(cos) times a symmetric matrix, so it takes the full path).
#include <Eigen/Core>

#include <vector>

#include "icobrdf/core/brdf_model.hpp"
#include "icobrdf/core/grid.hpp"
#include "icobrdf/core/lut.hpp"
#include "icobrdf/core/projection.hpp"

namespace icobrdf {

// Incident cells per block of the streaming projection: each thread holds kStreamingBlockRows x cells doubles
// per channel of LUT rows (2.6 MB at level 5; icobrdf/pipeline/resource_estimate.hpp counts them).
inline constexpr int kStreamingBlockRows = 32;

// One M x M coefficient matrix per model channel. Delta parts are added exactly in g form.
// `sampling_grid`, when given, supplies the cubature used for the cell averages of the LUT rows: the same
// cells as `grid` (same count and solid angles) with a cheaper rule, since each LUT entry averages over the
// product of two cells' rules (cost grows with the square of the points per cell).
std::vector<Eigen::MatrixXd> streaming_projection(const BrdfModel& model, const Grid& grid, const ProjectionOperator& proj,
                                                  bool cosine, LutSampling sampling = LutSampling::CellAverage,
                                                  const Grid* sampling_grid = nullptr);

// P^T F P of the g LUT of one delta part alone (F_ir = weight [r = image(i)] / Omega_r), in O(cells x modes):
// no LUT and no sampling. ArgumentError for a mirror part on a grid without the rotation-by-pi map.
Eigen::MatrixXd delta_projection(const DeltaPart& part, const Grid& grid, const ProjectionOperator& proj);

}  // namespace icobrdf
