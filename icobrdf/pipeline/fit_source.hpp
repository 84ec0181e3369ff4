#pragma once
// Fitting a SOURCE: one request (level, order, grid, sampling, ...) in, one spectrum out. The only place that
// builds a fitting grid and a projection context for a source; `icobrdf fit` and the bank builder go
// through it.
//
//   1. the fitting grid (icobrdf/mesh/tessellation.hpp build_fitting_grid): LUT rows and B sampled with the same
//      rule, one point per cell for centre sampling, the degree-2 cell rule for average sampling;
//   2. the projection context (icobrdf/core/fit/spectral_fit.hpp) for (grid, order, Gram tolerance); refused with an
//      UnsupportedError when the grid cannot resolve the order;
//   3. FitOptions from the request, LUT rows averaged over the grid's own cubature;
//   4. BrdfSource::fit (icobrdf/io/brdf_source.hpp).
// With order kChooseOrder (sources that choose their order, icobrdf/io/measured_sources.hpp chooses_order) the
// context is that of order 0: such fits use the grid only for the albedo figure.
// A FitContexts cache keeps grids and contexts across fits (the bank builder fits many materials on a few
// grids); without one, each call builds its own.
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <tuple>

#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/io/brdf_source.hpp"

namespace icobrdf {

struct FitRequest {
  int level = 4;
  int order = 8;                                        // kChooseOrder: the source chooses (chooses_order)
  GridKind grid_kind = GridKind::EqualArea;             // EqualArea or Geodesic (build_fitting_grid)
  LutSampling sampling = LutSampling::CellAverage;      // how the fitting grid samples each cell
  bool isotropic = false;                               // project onto the isotropic modes
  bool reciprocal = true;                               // false: keep the antisymmetric terms (FitOptions::reciprocal)
  bool cosine = false;                                  // fit g = f cos(theta_i) (forced for delta models)
  LowPassFilter filter;                                 // applied after the projection
  double gram_tolerance = kDefaultGramTolerance;        // largest Gram error accepted for (grid, order)
  FitProgress progress;                                 // optional, passed to the source's fit
  std::shared_ptr<const StreamingShare> share;          // optional: FitOptions::share (distributed projection)
};

// Grids and projection contexts by what defines them, built on first use. Safe to call from several threads
// at once (a bank build fits several materials at once, icobrdf/pipeline/bank_builder.hpp): one lock guards
// the tables, and a thread asking for an entry another is building waits for it (entries are built once).
class FitContexts {
 public:
  std::shared_ptr<const Grid> grid(const FitRequest& request);
  std::shared_ptr<const ProjectionContext> context(const FitRequest& request);
  // The largest order <= request.order that the request's grid supports within its Gram tolerance (-1: none),
  // and whose fit the memory holds (checked before the grid is built). A context asked for later at an order
  // up to that one is not checked again: the grid it already holds was counted in the first check, and
  // counting it twice refused the order the search had chosen (levels = [8]: "order 29 needs 19.6 GB; order
  // 28 fits" after 19.8 s, the level-8 grid's 2.1 GB counted in the need and missing from what was free).
  int supported_order(const FitRequest& request);

 private:
  std::mutex lock_;
  std::shared_ptr<const Grid> grid_locked(const FitRequest& request);
  using GridKey = std::tuple<int, GridKind, bool>;     // level, kind, centre
  using ContextKey = std::tuple<GridKey, int, double>; // grid, order, Gram tolerance
  std::map<GridKey, std::shared_ptr<const Grid>> grids_;
  std::map<ContextKey, std::shared_ptr<const ProjectionContext>> contexts_;
  std::map<ContextKey, int> supported_;
  std::map<GridKey, int> memory_checked_;  // per grid: the largest order whose fit the memory held when checked
};

struct FitResult {
  Spectrum spectrum;
  std::shared_ptr<const ProjectionContext> context;  // the grid and operators it was fitted with
};

FitResult fit_source(const BrdfSource& source, const FitRequest& request);
FitResult fit_source(const BrdfSource& source, const FitRequest& request, FitContexts& contexts);

}  // namespace icobrdf
