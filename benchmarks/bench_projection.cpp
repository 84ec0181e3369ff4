// Projection C = P^T F P of a dense LUT (icobrdf/core/projection/projection.hpp project_lut) against raw OpenBLAS doing the
// same products in the same run (icobrdf/lab/projection_benchmark.hpp); target at level 5, order 8: >= 60% of the
// FP64 peak in the GEMM part and at least as fast as raw OpenBLAS. The LUT is random and written before
// timing (no page faults in the timed region). OpenBLAS runs both association orders; the faster is the baseline.
//   bench_projection [--benchmark_filter=...]   (threads: OMP_NUM_THREADS and OPENBLAS_NUM_THREADS)
// Counters: gflops (2 cells^2 modes + 2 cells modes^2 flops per call); peak_gflops, the FP64 peak measured
// in-process on all threads at the dispatched vector width (icobrdf/lab/machine.hpp measure_fp64_peak_gflops, once per
// run), beside nominal_peak_gflops (threads x FP64 flops/cycle of the ISA compiled for x the clock of
// /proc/cpuinfo); divide gflops by peak_gflops for the ratio. OpenBLAS runs as the environment loads it; for
// OpenBLAS on its own kernel run `icobrdf bench project`, which also times it in a clean child process.
// Results: benchmarks/RESULTS.md, section "Projection".
#include <benchmark/benchmark.h>
#include <omp.h>

#include <memory>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/lab/machine.hpp"
#include "icobrdf/lab/projection_benchmark.hpp"
#include "icobrdf/mesh/tessellation.hpp"

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
    cache[level]->lut = lab::random_lut(g.cells());
  }
  return *cache[level];
}

double measured_peak(int threads) {
  static const double peak = lab::measure_fp64_peak_gflops(threads);
  return peak;
}

void report(benchmark::State& state, Eigen::Index c, Eigen::Index m) {
  const double flops = 2.0 * c * c * m + 2.0 * c * m * m;
  const int threads = omp_get_max_threads();
  state.counters["gflops"] = benchmark::Counter(flops / 1e9, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["peak_gflops"] = measured_peak(threads);
  state.counters["nominal_peak_gflops"] = lab::fp64_peak_gflops(threads);
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
  lab::set_blas_threads(omp_get_max_threads());
  const Eigen::Index c = s.lut.rows(), m = s.proj.P.cols();
  Eigen::MatrixXd tmp = pf_first ? Eigen::MatrixXd::Zero(m, c) : Eigen::MatrixXd::Zero(c, m), out = Eigen::MatrixXd::Zero(m, m);
  for (auto _ : state) {
    lab::blas_project(s.proj.P, s.lut, pf_first, tmp, out);
    benchmark::DoNotOptimize(out.data());
  }
  report(state, c, m);
}

BENCHMARK(BM_ProjectLut)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OpenBlas, pf_first, true)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_OpenBlas, fp_first, false)->Arg(4)->Arg(5)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
