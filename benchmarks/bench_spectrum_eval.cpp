// Spectrum evaluation f(w_i, w_r) = K(w_i)^T C K(w_r) at many direction pairs (icobrdf/core/spectrum/spectrum_ops.hpp
// evaluate_coefficients): issue 6 target ">= 10 million direction pairs per second at order 8", issue 17
// ">= 40 million on 2 cores". Per block of 192 pairs the basis of both sides is evaluated by the block
// kernel (BM_BasisBlock: directions per second, in cache), then the dispatched tile
// (icobrdf/core/spectrum/spectrum_tile.hpp, BM_SpectrumTile) forms sum_j K_j(w_r) sum_k K_k(w_i) C_kj. For a general C
// that needs M^2 = 2025 multiply-adds per pair at order 8 (4050 flops): at a 2-core FP64 peak P GFLOP/s
// it alone bounds the rate at P / 4050e-9 pairs/s (40 M pairs/s needs P >= 162); the basis of two
// directions per pair comes on top. An isotropic C (BM_EvaluateIsotropic) takes the sparse path.
//   bench_spectrum_eval [--benchmark_filter=...]   (threads: OMP_NUM_THREADS, default all cores)
// Counter pairs_per_s (wall clock). Results: benchmarks/RESULTS.md.
#include <benchmark/benchmark.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/spectrum/spectrum_tile.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"

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

// An isotropic C (coefficients_from_ibsss of random IBSSS coefficients): azimuthally block-diagonal, so the
// sparse tile path does 145 of the 2025 multiply-adds per pair at order 8 and the basis dominates.
void BM_EvaluateIsotropic(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const Eigen::Index pairs = state.range(1);
  std::mt19937_64 rng(7);
  const RowMatrix3d wi = random_directions(rng, pairs), wr = random_directions(rng, pairs);
  const Eigen::MatrixXd c = coefficients_from_ibsss(order, Eigen::VectorXd::Random(isotropic_mode_count(order)));
  for (auto _ : state) {
    const Eigen::VectorXd f = evaluate_coefficients(c, order, wi, wr);
    benchmark::DoNotOptimize(f.data());
  }
  state.counters["pairs_per_s"] = benchmark::Counter(static_cast<double>(pairs), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["threads"] = omp_get_max_threads();
}

// The dispatched tile alone on one block of 192 pairs in cache (one thread), general C: the bilinear
// form's share of the evaluation. Counter gflops = 2 M^2 flops per pair.
void BM_SpectrumTile(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const Eigen::Index block = 192;
  const int m = hemisphere_basis_count(order);
  std::mt19937_64 rng(7);
  const RowMatrix3d wi = random_directions(rng, block), wr = random_directions(rng, block);
  const PackedSpectrum packed = pack_spectrum(Eigen::MatrixXd::Random(m, m), order);
  Eigen::MatrixXd ki = Eigen::MatrixXd::Zero(block, m), kr = Eigen::MatrixXd::Zero(block, spectrum_tile_columns(packed));
  hemisphere_basis_block(order, block, wi.data(), ki.data(), block);
  hemisphere_basis_block(order, block, wr.data(), kr.data(), block);
  Eigen::VectorXd f(block);
  for (auto _ : state) {
    spectrum_tile(packed, block, ki.data(), kr.data(), block, f.data());
    benchmark::DoNotOptimize(f.data());
  }
  state.counters["pairs_per_s"] = benchmark::Counter(static_cast<double>(block), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["gflops"] = benchmark::Counter(2e-9 * m * m * block, benchmark::Counter::kIsIterationInvariantRate);
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

// The block kernel alone: blocks of B directions (256; 192 as in evaluate_coefficients) into one B x M buffer that stays in cache (the basis
// part of the spectrum evaluation, which needs two directions per pair). One thread.
void BM_BasisBlock(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const Eigen::Index n = state.range(1), block = state.range(2);
  std::mt19937_64 rng(7);
  const RowMatrix3d d = random_directions(rng, n);
  std::vector<double> k(static_cast<size_t>(block * hemisphere_basis_count(order)));
  for (auto _ : state) {
    for (Eigen::Index r0 = 0; r0 < n; r0 += block)
      hemisphere_basis_block(order, std::min(block, n - r0), d.data() + 3 * r0, k.data(), block);
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
BENCHMARK(BM_EvaluateIsotropic)->Args({8, 1 << 20})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SpectrumTile)->Arg(8)->Arg(16)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BasisMatrix)->Args({8, 1 << 20})->Args({8, 1 << 14})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BasisBlock)->Args({8, 1 << 14, 256})->Args({8, 1 << 14, 192})->Args({32, 1 << 12, 256})->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_BasisOneByOne)->Args({8, 1 << 14})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
