#pragma once
// From a BRDF (analytic model or LUT) on a grid to its Spectrum: the pipeline behind `icobrdf fit` and
// the bank builder.
//
//   1. B, G and the projection P for (grid, order); refused when the grid cannot resolve the order
//      (icobrdf/core/projection/discrete_basis.hpp, UnsupportedError naming the largest supported order).
//   2. C = P^T F P per channel: by streaming for models (the LUT is never materialized), or from a LUT.
//   3. Helmholtz projection of f spectra: C <- (C + C^T)/2, the closest reciprocal spectrum (paper eq. 21);
//      the relative norm of the removed antisymmetric part is recorded as reciprocity_violation. With
//      options.reciprocal false C is kept whole: its antisymmetric part is the data's antisymmetric terms
//      (icobrdf/core/basis/antisymmetric_modes.hpp; paper section 2B), for reproducing a non-reciprocal
//      measurement.
//      Spectra of g = f cos(theta_i) are not symmetrized (g is not reciprocal); for them the figure
//      records the asymmetry of g's spectrum.
//   4. Isotropic projection on request (isotropic_part), recording the anisotropic energy fraction.
//   5. Low-pass filter on request.
//   6. Figures: Gram error of the grid, maximum directional albedo over the cells' directions computed
//      from the final spectrum (white furnace).
#include <memory>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/fit/fit_progress.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"

namespace icobrdf {

// The white furnace of a g spectrum divides a(w) by cos(theta_i): cells whose representative direction has
// cos(theta) below this (within 0.06 degrees of the horizon) would amplify a's truncation error over 1000
// times, so they are left out of max_albedo (and of the albedo check of icobrdf/pipeline/reflectance_check.hpp).
inline constexpr double kGrazingCellCos = 1e-3;

struct FitOptions {
  int order = 8;
  bool isotropic = false;
  bool reciprocal = true;  // false: keep C's antisymmetric part (step 3 above)
  bool cosine = false;  // project g = f cos(theta_i); forced for models with delta parts
  LowPassFilter filter;
  LutSampling sampling = LutSampling::CellAverage;
  double gram_tolerance = kDefaultGramTolerance;
  ProjectionOperator::Kind projection = ProjectionOperator::Kind::LeastSquares;
  FitProgress progress;  // optional: fits of scattered samples report their stages (icobrdf/core/fit/fit_progress.hpp)
  // Optional: this process's share of a model's streaming projection, the other shares projected elsewhere
  // (icobrdf/core/projection/streaming_projection.hpp StreamingShare; icobrdf/cluster/distributed_projection.hpp under
  // mpirun). Fits of scattered samples (MERL tables, CSV samples) split their passes over the samples
  // through its sample_sum (icobrdf/core/fit/sample_fit.hpp SampleFitSplit); fits of LUTs do not use it.
  std::shared_ptr<const StreamingShare> share;
};

// FitOptions::order for sources that choose their order (fits of scattered samples: K-fold cross-validation,
// icobrdf/core/fit/sample_fit_selection.hpp); other sources refuse it.
inline constexpr int kChooseOrder = -1;

// The operators for one (grid, order), built once and shared by many fits.
// `sampling_grid` (optional): the same cells with a cheaper cubature, used only to sample LUT rows of
// models (icobrdf/core/projection/streaming_projection.hpp); B is always built with `grid`'s own rule.
struct ProjectionContext {
  std::shared_ptr<const Grid> grid;
  std::shared_ptr<const Grid> sampling_grid;
  DiscreteBasis basis;
  ProjectionOperator projection;
  // Operators split by rows over processes (make_split_projection_context): then basis holds G and its
  // figures only (B empty, grid_cells set), projection.P is empty, and fit_model projects through the
  // split (FitOptions::share->rows, the same exchange); fit_lut refuses.
  std::shared_ptr<const SplitOperators> split;
};
ProjectionContext make_projection_context(std::shared_ptr<const Grid> grid, int order,
                                          double gram_tolerance = kDefaultGramTolerance,
                                          ProjectionOperator::Kind kind = ProjectionOperator::Kind::LeastSquares,
                                          std::shared_ptr<const Grid> sampling_grid = nullptr);

// Collective over the exchange's processes (one sum of G): each holds its block's rows of P.
ProjectionContext make_split_projection_context(std::shared_ptr<const Grid> grid, int order, double gram_tolerance, RowSplitExchange& exchange);

Spectrum fit_model(const BrdfModel& model, const ProjectionContext& ctx, const FitOptions& options);
Spectrum fit_lut(const Lut& lut, const std::string& source, const ProjectionContext& ctx, const FitOptions& options);

// Orthogonal projection onto BRDFs invariant under rotation about the normal and under reflection in the
// vertical planes (functions of theta_i, theta_r and |phi_i - phi_r|): averages C over those symmetries.
// Keeps only entries between K_n^l and K_m^l' with |l| = |l'|, sets C(n^l, m^l) = C(n^-l, m^-l) to their
// mean and the cross entries C(n^l, m^-l) to 0. Does not symmetrize (works for g spectra as well);
// for a symmetric C it is the projection onto the span of the isotropic modes I_nm^l.
Eigen::MatrixXd isotropic_part(const Eigen::MatrixXd& c, int order);

}  // namespace icobrdf
