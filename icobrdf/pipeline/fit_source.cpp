#include "icobrdf/pipeline/fit_source.hpp"
#include "icobrdf/pipeline/fit_order.hpp"

#include <algorithm>

#include "icobrdf/io/measured_sources.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/pipeline/resource_estimate.hpp"

namespace icobrdf {
namespace {

std::tuple<int, GridKind, bool> grid_key(const FitRequest& r) {
  return {r.level, r.grid_kind, r.sampling == LutSampling::CellCentre};
}

}  // namespace

std::shared_ptr<const Grid> FitContexts::grid(const FitRequest& request) {
  std::lock_guard<std::mutex> g(lock_);
  return grid_locked(request);
}

std::shared_ptr<const Grid> FitContexts::grid_locked(const FitRequest& request) {
  auto& g = grids_[grid_key(request)];
  if (!g)
    g = std::make_shared<const Grid>(build_fitting_grid(request.level, request.grid_kind, request.sampling == LutSampling::CellCentre));
  return g;
}

std::shared_ptr<const ProjectionContext> FitContexts::context(const FitRequest& request) {
  std::lock_guard<std::mutex> lock(lock_);
  auto& c = contexts_[{grid_key(request), request.order, request.gram_tolerance}];
  RowSplitExchange* rows = request.share ? request.share->rows.get() : nullptr;
  // One channel: the channel terms are small beside the C x M matrices that decide whether it fits.
  const auto checked = memory_checked_.find(grid_key(request));
  const bool held = !rows && checked != memory_checked_.end() && request.order <= checked->second;
  if (!c && !held) require_model_fit_memory(request.level, request.order, 1, "a fit", rows ? rows->parts() : 1);
  if (!c && rows)
    c = std::make_shared<const ProjectionContext>(make_split_projection_context(grid_locked(request), request.order, request.gram_tolerance, *rows));
  if (!c) c = std::make_shared<const ProjectionContext>(make_projection_context(grid_locked(request), request.order, request.gram_tolerance));
  return c;
}

int FitContexts::supported_order(const FitRequest& request) {
  std::lock_guard<std::mutex> lock(lock_);
  const ContextKey key{grid_key(request), request.order, request.gram_tolerance};
  const auto it = supported_.find(key);
  if (it != supported_.end()) return it->second;
  // The basis is built at the largest order whose fit the memory holds: a search need not be refused for an
  // order it may never reach, and orders beyond that one are never tried.
  const int in_memory = largest_order_in_memory(request.level, request.order, 1);
  if (in_memory < 0) require_model_fit_memory(request.level, 0, 1, "a fit");
  int& checked = memory_checked_[grid_key(request)];
  checked = std::max(checked, in_memory);
  return supported_[key] = largest_supported_order(build_discrete_basis(*grid_locked(request), in_memory), request.gram_tolerance);
}

int fit_order_for(const BrdfSource& source, std::optional<int> order) {
  if (order) return *order;
  return chooses_order(source) ? kChooseOrder : kDefaultFitOrder;
}

FitResult fit_source(const BrdfSource& source, const FitRequest& request) {
  FitContexts contexts;
  return fit_source(source, request, contexts);
}

FitResult fit_source(const BrdfSource& source, const FitRequest& request, FitContexts& contexts) {
  FitResult r;
  if (request.order == kChooseOrder) {
    FitRequest grid_only = request;
    grid_only.order = 0;
    r.context = contexts.context(grid_only);
  } else {
    r.context = contexts.context(request);
  }
  FitOptions o;
  o.order = request.order;
  o.progress = request.progress;
  o.share = request.share;
  o.isotropic = request.isotropic;
  o.reciprocal = request.reciprocal;
  o.cosine = request.cosine;
  o.filter = request.filter;
  o.gram_tolerance = request.gram_tolerance;
  o.sampling = LutSampling::CellAverage;  // over the context's cubature (one point per cell for centre sampling)
  r.spectrum = source.fit(*r.context, o);
  return r;
}

}  // namespace icobrdf
