// Spectrum evaluation f(w_i, w_r) = K(w_i)^T C K(w_r) at many direction pairs (core/spectrum_ops.hpp
// evaluate_coefficients): issue 6 target ">= 10 million direction pairs per second at order 8". The basis
// is evaluated for all incident and all remitted directions in batches (K(w_i), K(w_r): pairs x modes),
// then K(w_i) C by a GEMM and a row-wise dot with K(w_r).
//   bench_spectrum_eval [--benchmark_filter=...]   (threads: OMP_NUM_THREADS, default all cores)
// Counter pairs_per_s (wall clock). Results: benchmarks/RESULTS.md, section "Spectrum evaluation".
#include <benchmark/benchmark.h>
#include <omp.h>

#include <cmath>
#include <random>
#include <vector>

#include "core/hemisphere_basis.hpp"
#include "core/spectrum_ops.hpp"

namespace {

using namespace icobrdf;

RowMatrix3d random_directions(std::mt19937_64& rng, Eigen::Index n) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  RowMatrix3d d(n, 3);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double z = u(rng), s = std::sqrt(1.0 - z * z), p = 2.0 * M_PI * u(rng);
    d.row(k) << s * std::cos(p), s * std::sin(p), z;
  }
  return d;
}

void BM_EvaluateCoefficients(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const Eigen::Index pairs = state.range(1);
  std::mt19937_64 rng(7);
  const RowMatrix3d wi = random_directions(rng, pairs), wr = random_directions(rng, pairs);
  const int m = hemisphere_basis_count(order);
  const Eigen::MatrixXd c = Eigen::MatrixXd::Random(m, m);
  for (auto _ : state) {
    const Eigen::VectorXd f = evaluate_coefficients(c, order, wi, wr);
    benchmark::DoNotOptimize(f.data());
  }
  state.counters["pairs_per_s"] = benchmark::Counter(static_cast<double>(pairs), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["threads"] = omp_get_max_threads();
}

// The basis evaluation alone (one side), directions per second.
void BM_BasisMatrix(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const Eigen::Index n = state.range(1);
  std::mt19937_64 rng(7);
  const RowMatrix3d d = random_directions(rng, n);
  for (auto _ : state) {
    const Eigen::MatrixXd k = hemisphere_basis_matrix(order, d);
    benchmark::DoNotOptimize(k.data());
  }
  state.counters["dirs_per_s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

// The one-direction evaluator in a loop (the path before the lane-parallel one), for comparison.
void BM_BasisOneByOne(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const Eigen::Index n = state.range(1);
  std::mt19937_64 rng(7);
  const RowMatrix3d d = random_directions(rng, n);
  std::vector<double> k(static_cast<size_t>(hemisphere_basis_count(order)));
  for (auto _ : state) {
    for (Eigen::Index r = 0; r < n; ++r) hemisphere_basis_eval(order, d.row(r).transpose(), k.data());
    benchmark::DoNotOptimize(k.data());
  }
  state.counters["dirs_per_s"] = benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(BM_EvaluateCoefficients)->Args({8, 1 << 20})->Args({8, 1 << 14})->Args({16, 1 << 18})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BasisMatrix)->Args({8, 1 << 20})->Args({8, 1 << 14})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BasisOneByOne)->Args({8, 1 << 14})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
