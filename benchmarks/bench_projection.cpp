// Projection C = P^T F P of a dense LUT (core/projection.hpp project_lut) against raw OpenBLAS doing the
// same products in the same run: issue 6 target "level 5, order 8: >= 60% of the FP64 peak in the GEMM
// part and at least as fast as raw OpenBLAS". The LUT is random and written before timing (no page
// faults in the timed region). OpenBLAS runs both association orders; the faster is the baseline.
//   bench_projection [--benchmark_filter=...]   (threads: OMP_NUM_THREADS and OPENBLAS_NUM_THREADS)
// Counters: gflops (2 cells^2 modes + 2 cells modes^2 flops per call), peak_ratio = gflops / peak, with
// peak = cli/machine.hpp fp64_peak_gflops: threads x FP64 flops/cycle of the ISA compiled for x the clock of /proc/cpuinfo.
// Results: benchmarks/RESULTS.md, section "Projection".
#include <benchmark/benchmark.h>
#include <cblas.h>
#include <omp.h>

#include <fstream>
#include <memory>
#include <random>
#include <string>

#include "cli/machine.hpp"
#include "core/discrete_basis.hpp"
#include "core/projection.hpp"
#include "mesh/tessellation.hpp"

namespace {

using namespace icobrdf;

constexpr int kOrder = 8;

struct Setup {
  ProjectionOperator proj;
  Eigen::MatrixXd lut;
};

const Setup& setup(int level) {
  static std::unique_ptr<Setup> cache[9];
  if (!cache[level]) {
    cache[level] = std::make_unique<Setup>();
    const Grid g = with_centre_cubature(build_equal_area_grid(level));
    cache[level]->proj = make_projection(build_discrete_basis(g, kOrder));
    Eigen::MatrixXd f(g.cells(), g.cells());
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (Eigen::Index k = 0; k < f.size(); ++k) f.data()[k] = u(rng);
    cache[level]->lut = std::move(f);
  }
  return *cache[level];
}

void report(benchmark::State& state, Eigen::Index c, Eigen::Index m) {
  const double flops = 2.0 * c * c * m + 2.0 * c * m * m;
  const int threads = omp_get_max_threads();
  state.counters["gflops"] = benchmark::Counter(flops / 1e9, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["peak_gflops"] = icobrdf::cli::fp64_peak_gflops(threads);
  state.counters["threads"] = threads;
  state.counters["cells"] = static_cast<double>(c);
}

void BM_ProjectLut(benchmark::State& state) {
  const auto& s = setup(static_cast<int>(state.range(0)));
  Eigen::MatrixXd c;
  for (auto _ : state) {
    c = project_lut(s.proj, s.lut);
    benchmark::DoNotOptimize(c.data());
  }
  report(state, s.lut.rows(), s.proj.P.cols());
}

// Raw OpenBLAS: (P^T F) P when pf_first, else P^T (F P); column-major as Eigen stores.
void BM_OpenBlas(benchmark::State& state, bool pf_first) {
  const auto& s = setup(static_cast<int>(state.range(0)));
  openblas_set_num_threads(omp_get_max_threads());
  const int c = static_cast<int>(s.lut.rows()), m = static_cast<int>(s.proj.P.cols());
  const double* p = s.proj.P.data();
  Eigen::MatrixXd tmp = pf_first ? Eigen::MatrixXd::Zero(m, c) : Eigen::MatrixXd::Zero(c, m), out = Eigen::MatrixXd::Zero(m, m);
  for (auto _ : state) {
    if (pf_first) {
      cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, m, c, c, 1.0, p, c, s.lut.data(), c, 0.0, tmp.data(), m);
      cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, m, m, c, 1.0, tmp.data(), m, p, c, 0.0, out.data(), m);
    } else {
      cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, c, m, c, 1.0, s.lut.data(), c, p, c, 0.0, tmp.data(), c);
      cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, m, m, c, 1.0, p, c, tmp.data(), c, 0.0, out.data(), m);
    }
    benchmark::DoNotOptimize(out.data());
  }
  report(state, c, m);
}

BENCHMARK(BM_ProjectLut)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OpenBlas, pf_first, true)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OpenBlas, fp_first, false)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
