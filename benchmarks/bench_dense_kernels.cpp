// The dense kernels of the sample fits (icobrdf/core/fit/dense_kernels.hpp): the symmetric rank-k update G += A^T A
// of one assembly panel (the 20,000-sample order-10 fit: 2,211 unknowns, panels of 1,809 rows) and the
// Cholesky factorization of G, with Eigen's kernels and with OpenBLAS's as loaded (its core in the label:
// run once as is and once with OPENBLAS_CORETYPE=SkylakeX, say, to compare OpenBLAS's kernels). Counters:
// GFLOP/s (the update n k^2 flops, the factorization k^3 / 3) and the fraction of the FP64 peak measured in
// the same process on the same threads (icobrdf/lab/machine.hpp), and which set fit_dense_kernels() picks here.
// Results: benchmarks/RESULTS.md, section "Dense kernels of the sample fits".
#include <benchmark/benchmark.h>

#include <Eigen/Core>

#include <omp.h>

#include <string>

#include "icobrdf/core/fit/dense_kernels.hpp"
#include "icobrdf/blas/blas_dense_kernels.hpp"
#include "icobrdf/lab/machine.hpp"

extern "C" char* openblas_get_corename();

namespace {

constexpr Eigen::Index kUnknowns = 2211;  // order 10, general Helmholtz modes
constexpr Eigen::Index kPanelRows = 1809;  // icobrdf/core/fit/sample_fit.cpp: 4e6 / unknowns rows per panel

double peak() {
  static const double p = icobrdf::lab::measure_fp64_peak_gflops(omp_get_max_threads());
  return p;
}

const icobrdf::DenseKernels& kernels(int which) {
  return which == 0 ? icobrdf::eigen_dense_kernels() : icobrdf::blas_dense_kernels();
}

void label(benchmark::State& state, int which) {
  std::string l = which == 0 ? "Eigen" : std::string("OpenBLAS ") + openblas_get_corename();
  if (&kernels(which) == &icobrdf::fit_dense_kernels()) l += " (fit_dense_kernels' choice)";
  state.SetLabel(l);
}

void BM_RankUpdate(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(kPanelRows, kUnknowns);
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(kUnknowns, kUnknowns);
  for (auto _ : state) icobrdf::rank_update_lower(&kernels(which), g, a);
  const double flops = static_cast<double>(kPanelRows) * kUnknowns * kUnknowns;
  state.counters["GFLOP/s"] = benchmark::Counter(flops * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["peak GFLOP/s"] = peak();
  label(state, which);
}

void BM_Cholesky(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(2 * kUnknowns, kUnknowns);
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(kUnknowns, kUnknowns);
  icobrdf::rank_update_lower(&icobrdf::eigen_dense_kernels(), g, a);
  g.triangularView<Eigen::StrictlyUpper>() = g.transpose();
  for (auto _ : state) {
    auto llt = icobrdf::cholesky(&kernels(which), g);
    benchmark::DoNotOptimize(llt.info());
  }
  const double flops = static_cast<double>(kUnknowns) * kUnknowns * kUnknowns / 3.0;
  state.counters["GFLOP/s"] = benchmark::Counter(flops * 1e-9, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["peak GFLOP/s"] = peak();
  label(state, which);
}

}  // namespace

BENCHMARK(BM_RankUpdate)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
BENCHMARK(BM_Cholesky)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(1.0);
BENCHMARK_MAIN();
