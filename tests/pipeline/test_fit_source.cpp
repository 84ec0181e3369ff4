// icobrdf/pipeline/fit_source.hpp: one request gives the spectrum that the explicit sequence (fitting grid,
// projection context, FitOptions, BrdfSource::fit) gives, and the context cache shares what it can.
#include <gtest/gtest.h>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/pipeline/fit_report.hpp"
#include "icobrdf/pipeline/fit_source.hpp"
#include "icobrdf/pipeline/resource_estimate.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

TEST(FitSource, EqualsTheExplicitSequence) {
  const auto src = open_source("model:0.5*lambert+0.5*ggx:alpha=0.4");
  for (const LutSampling sampling : {LutSampling::CellAverage, LutSampling::CellCentre}) {
    FitRequest r;
    r.level = 2;
    r.order = 3;
    r.sampling = sampling;
    r.isotropic = true;
    const FitResult got = fit_source(*src, r);
    const auto grid = std::make_shared<const Grid>(build_fitting_grid(2, GridKind::EqualArea, sampling == LutSampling::CellCentre));
    FitOptions o;
    o.order = 3;
    o.isotropic = true;
    const Spectrum want = src->fit(make_projection_context(grid, 3), o);
    ASSERT_EQ(got.spectrum.channels.size(), want.channels.size());
    EXPECT_EQ(got.spectrum.channels[0], want.channels[0]);  // the same operations: bit for bit
    EXPECT_TRUE(got.spectrum.isotropic);
    EXPECT_EQ(got.context->grid->cells(), grid->cells());
    EXPECT_EQ(got.context->grid->cubature_points.rows(), grid->cubature_points.rows());
  }
}

TEST(FitSource, FilterAndCosineReachTheFit) {
  const auto src = open_source("model:phong:n=6");
  FitRequest r;
  r.level = 2;
  r.order = 3;
  r.filter = parse_lowpass_filter("hann");
  r.cosine = true;
  const Spectrum s = fit_source(*src, r).spectrum;
  EXPECT_EQ(s.filter, "hann");
  EXPECT_TRUE(s.cosine);
}

TEST(FitSource, ContextsAreSharedPerGridOrderAndTolerance) {
  FitContexts contexts;
  FitRequest a;
  a.level = 1;
  a.order = 1;
  FitRequest b = a;
  b.isotropic = true;  // not part of the context
  EXPECT_EQ(contexts.context(a), contexts.context(b));
  FitRequest c = a;
  c.sampling = LutSampling::CellCentre;
  EXPECT_NE(contexts.grid(a), contexts.grid(c));
  EXPECT_NE(contexts.context(a), contexts.context(c));
  FitRequest d = a;
  d.order = 0;
  EXPECT_EQ(contexts.grid(a), contexts.grid(d));
  EXPECT_NE(contexts.context(a), contexts.context(d));
}

TEST(FitSource, SupportedOrderIsCappedAndRefusalsNameTheLimit) {
  FitContexts contexts;
  FitRequest r;
  r.level = 1;
  r.order = 16;
  const int supported = contexts.supported_order(r);
  EXPECT_GE(supported, 0);
  EXPECT_LT(supported, 16);
  r.order = 0;
  EXPECT_EQ(contexts.supported_order(r), 0);
  r.order = 30;
  EXPECT_THROW(fit_source(*open_source("model:lambert"), r), UnsupportedError);
}

TEST(FitSource, AnOrderTheMemoryCheckAllowedIsNotRefusedOnceTheGridIsHeld) {
  // The search asks supported_order (memory checked before the grid exists: the estimate includes the
  // grid), builds the grid, then asks for the context at that order. With the memory now smaller by the
  // grid it holds, a second check would refuse the order it was given ("order 29 needs 19.6 GB; order 28
  // fits" at level 8): the context is made. An order beyond the one checked is still checked.
  struct BudgetGuard {
    ~BudgetGuard() { set_memory_budget(0); }
  } guard;
  FitRequest r;
  r.level = 3;
  r.order = 6;
  const double need = model_fit_bytes(3, 6, 1, estimate_threads());
  set_memory_budget(need);
  FitContexts contexts;
  const int top = contexts.supported_order(r);
  ASSERT_EQ(top, 6) << "level 3 resolves order 6 (Gram error within 0.1)";
  set_memory_budget(need - grid_bytes(3));  // what is left once this process holds the grid
  r.order = top;
  EXPECT_NO_THROW(contexts.context(r));
  r.order = top + 1;
  EXPECT_THROW(contexts.context(r), ResourceError);
  FitContexts fresh;  // without the earlier check, the same order is checked and refused
  r.order = top;
  EXPECT_THROW(fresh.context(r), ResourceError);
}

TEST(FitReportOf, AModelKeepsNoSampleFitAndRanksSayWhatTheySplit) {
  const auto source = open_source("model:lambert:albedo=0.5");
  FitRequest r;
  r.level = 2;
  r.order = 2;
  const FitResult fit = fit_source(*source, r);
  const FitReport report = fit_report_of(fit, *source);
  EXPECT_EQ(report.fit, &fit);
  EXPECT_EQ(report.checked, nullptr);
  EXPECT_EQ(report.kernels, nullptr);
  EXPECT_EQ(report.missing_samples, -1);
  nlohmann::json rows, samples, none;
  add_rank_split_json(rows, 4, 6, 0, {1e6, 2e6, 3e6, 4e6});
  add_rank_split_json(samples, 2, 0, 3, {1e6, 1e6});
  add_rank_split_json(none, 2, 0, 0, {1e6, 1e6});
  EXPECT_EQ(rows["split"], "operators by rows");
  EXPECT_EQ(rows["ranks"], 4);
  EXPECT_EQ(rows["peak_rss_bytes_per_rank"].size(), 4u);
  EXPECT_EQ(samples["split"], "samples");
  EXPECT_EQ(none["split"], "none");
}

}  // namespace
}  // namespace icobrdf
