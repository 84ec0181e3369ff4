// Cell lookup throughput: CellLocator::locate on random upper-hemisphere directions (uniform in solid
// angle), single thread. items_per_second = lookups per second.
// Also: grid build time per level (equal-area, default cubature degree).
#include <benchmark/benchmark.h>

#include <random>

#include "icobrdf/mesh/cell_locator.hpp"
#include "icobrdf/mesh/tessellation.hpp"

namespace {

icobrdf::RowMatrix3d random_directions(int count) {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  icobrdf::RowMatrix3d d(count, 3);
  for (int k = 0; k < count; ++k) {
    const double z = u(rng), phi = 2.0 * M_PI * u(rng), s = std::sqrt(1.0 - z * z);
    d.row(k) << s * std::cos(phi), s * std::sin(phi), z;
  }
  return d;
}

void BM_Locate(benchmark::State& state, const char* kind) {
  const int level = static_cast<int>(state.range(0));
  const icobrdf::CellLocator loc(level, kind);
  const int count = 1 << 16;
  const icobrdf::RowMatrix3d dirs = random_directions(count);
  Eigen::VectorXi cells;
  for (auto _ : state) {
    loc.locate(dirs, cells);
    benchmark::DoNotOptimize(cells.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * count);
}
BENCHMARK_CAPTURE(BM_Locate, equal_area, "equal-area")->Arg(0)->Arg(5)->Arg(8);
BENCHMARK_CAPTURE(BM_Locate, geodesic, "geodesic")->Arg(5)->Arg(8);

void BM_BuildEqualAreaGrid(benchmark::State& state) {
  const int level = static_cast<int>(state.range(0));
  for (auto _ : state) {
    icobrdf::Grid g = icobrdf::build_equal_area_grid(level);
    benchmark::DoNotOptimize(g.cubature_points.data());
  }
  state.SetItemsProcessed(state.iterations() * (10LL * (1LL << (2 * level)) + (2LL << level)));
}
BENCHMARK(BM_BuildEqualAreaGrid)->DenseRange(0, 8)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
