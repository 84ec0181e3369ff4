// Building the sampled basis (icobrdf/core/projection/discrete_basis.hpp) on the level-5 equal-area grid with its default
// cell cubature (287 300 points): issue 6 target "B with cell cubature at level 5, order 32 in <= 50 ms".
// build_discrete_basis returns B (cell averages of the 561 K_n^l), the Gram matrix G = B^T W B, its error
// max|G - I| and its condition number (eigenvalues of G). The grid's cubature is D2-equivariant, so only
// one cell per orbit is evaluated (counter evaluated_cells) and G is summed over those cells within the
// four symmetry classes. The full-matrix eigenvalues and a plain GEMM for G are timed separately below.
// values_per_s counts all points x modes, as if every cell were evaluated.
//   bench_basis_build [--benchmark_filter=...]   (threads: OMP_NUM_THREADS, default all cores)
// Results: benchmarks/RESULTS.md, section "Building B".
#include <benchmark/benchmark.h>
#include <omp.h>

#include <Eigen/Eigenvalues>
#include <memory>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/mesh/tessellation.hpp"

namespace {

using namespace icobrdf;

const Grid& grid(int level) {
  static std::unique_ptr<Grid> cache[9];
  if (!cache[level]) cache[level] = std::make_unique<Grid>(build_equal_area_grid(level));
  return *cache[level];
}

void BM_BuildDiscreteBasis(benchmark::State& state) {
  const Grid& g = grid(static_cast<int>(state.range(0)));
  const int order = static_cast<int>(state.range(1));
  int evaluated = 0;
  for (auto _ : state) {
    auto b = build_discrete_basis(g, order);
    benchmark::DoNotOptimize(b.B.data());
    evaluated = b.evaluated_cells;
  }
  state.counters["cells"] = g.cells();
  state.counters["evaluated_cells"] = evaluated;  // one per D2 orbit when the cubature is equivariant
  state.counters["points"] = static_cast<double>(g.cubature_points.rows());
  state.counters["modes"] = hemisphere_basis_count(order);
  state.counters["threads"] = omp_get_max_threads();
  // K_j at every cubature point: points x modes basis values per build.
  state.counters["values_per_s"] = benchmark::Counter(static_cast<double>(g.cubature_points.rows()) * hemisphere_basis_count(order),
                                                      benchmark::Counter::kIsIterationInvariantRate);
}

// The eigenvalues of a Gram matrix of the same size alone (SelfAdjointEigenSolver, values only).
void BM_GramEigenvalues(benchmark::State& state) {
  const Grid& g = grid(static_cast<int>(state.range(0)));
  const auto b = build_discrete_basis(g, static_cast<int>(state.range(1)));
  for (auto _ : state) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(b.G, Eigen::EigenvaluesOnly);
    benchmark::DoNotOptimize(eig.eigenvalues().data());
  }
}

// The Gram product B^T W B alone, as a plain GEMM.
void BM_GramGemm(benchmark::State& state) {
  const Grid& g = grid(static_cast<int>(state.range(0)));
  const auto b = build_discrete_basis(g, static_cast<int>(state.range(1)));
  for (auto _ : state) {
    const Eigen::MatrixXd gram = b.B.transpose() * b.W.asDiagonal() * b.B;
    benchmark::DoNotOptimize(gram.data());
  }
  const double flops = 2.0 * b.B.rows() * b.B.cols() * b.B.cols();
  state.counters["gflops"] = benchmark::Counter(flops / 1e9, benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(BM_BuildDiscreteBasis)->Args({5, 32})->Args({5, 8})->Args({4, 16})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GramEigenvalues)->Args({5, 32})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_GramGemm)->Args({5, 32})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
