// Streaming projection of an analytic GGX material without its LUT (icobrdf/core/projection/streaming_projection.hpp), the
// path behind `icobrdf fit`: issue 6 target "level 5, order 8 in <= 0.25 s on 2 cores".
//   bench_streaming [--benchmark_filter=...]   (threads: OMP_NUM_THREADS, default all cores)
// Grids: "fit" = build_fitting_grid(level, GridKind::EqualArea, false), the cell-averaged sampling `icobrdf fit`
// and the bank builder use (degree-kLutSamplingDegree rule in every cell, for B and the LUT rows alike);
// "centre" = one point per cell (centre sampling). Counters: model evaluations per second (the product of
// the two cells' rules for every LUT entry), cells, points per cell; the components (model evaluation of
// LUT rows alone, the two GEMMs) are timed separately so the split of the time is visible.
// Results: benchmarks/RESULTS.md, section "Streaming projection".
#include <benchmark/benchmark.h>
#include <omp.h>

#include <memory>
#include <string>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "icobrdf/mesh/tessellation.hpp"

namespace {

using namespace icobrdf;

constexpr int kOrder = 8;
constexpr const char* kModel = "ggx:alpha=0.3";

struct Setup {
  std::shared_ptr<const Grid> grid;
  ProjectionContext ctx;
};

const Setup& setup(int level, bool centre) {
  static std::unique_ptr<Setup> cache[2][9];
  auto& s = cache[centre ? 1 : 0][level];
  if (!s) {
    s = std::make_unique<Setup>();
    s->grid = std::make_shared<const Grid>(build_fitting_grid(level, GridKind::EqualArea, centre));
    s->ctx = make_projection_context(s->grid, kOrder);
  }
  return *s;
}

void counters(benchmark::State& state, const Grid& g) {
  const double q = static_cast<double>(g.cubature_points.rows());
  state.counters["cells"] = g.cells();
  state.counters["points_per_cell"] = q / g.cells();
  state.counters["threads"] = omp_get_max_threads();
  state.counters["evals_per_s"] = benchmark::Counter(q * q, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_StreamingGgx(benchmark::State& state, bool centre) {
  const auto& s = setup(static_cast<int>(state.range(0)), centre);
  const auto model = parse_model(kModel);
  FitOptions o;
  o.order = kOrder;
  o.sampling = centre ? LutSampling::CellCentre : LutSampling::CellAverage;
  for (auto _ : state) {
    auto c = streaming_projection(*model, *s.grid, s.ctx.projection, false, o.sampling);
    benchmark::DoNotOptimize(c[0].data());
  }
  counters(state, *s.grid);
}

// The model-evaluation part alone: LUT rows of one block of 32 incident cells (the streaming block),
// scaled to all cells in the counter.
void BM_LutRowsGgx(benchmark::State& state, bool centre) {
  const auto& s = setup(static_cast<int>(state.range(0)), centre);
  const auto model = parse_model(kModel);
  std::vector<Eigen::MatrixXd> rows;
  const int block = 32;
  for (auto _ : state) {
    sample_lut_rows(*model, *s.grid, false, centre ? LutSampling::CellCentre : LutSampling::CellAverage, 0, block, rows);
    benchmark::DoNotOptimize(rows[0].data());
  }
  const double q = static_cast<double>(s.grid->cubature_points.rows());
  const double qin = static_cast<double>(s.grid->cubature_offsets[block]);
  state.counters["evals_per_s"] = benchmark::Counter(qin * q, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["blocks_per_lut"] = static_cast<double>(s.grid->cells()) / block;
}

// The GEMM part alone: T = F P for all rows and C = P^T T, with a resident F (cells x cells).
void BM_StreamingGemms(benchmark::State& state) {
  const auto& s = setup(static_cast<int>(state.range(0)), false);
  const auto& p = s.ctx.projection.P;
  const Eigen::MatrixXd f = Eigen::MatrixXd::Random(p.rows(), p.rows());
  for (auto _ : state) {
    const Eigen::MatrixXd t = f * p;
    const Eigen::MatrixXd c = p.transpose() * t;
    benchmark::DoNotOptimize(c.data());
  }
  const double flops = 2.0 * p.rows() * p.rows() * p.cols() + 2.0 * p.rows() * p.cols() * p.cols();
  state.counters["gflops"] = benchmark::Counter(flops / 1e9, benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK_CAPTURE(BM_StreamingGgx, fit, false)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_StreamingGgx, centre, true)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_LutRowsGgx, fit, false)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_StreamingGemms)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
