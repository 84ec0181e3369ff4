// Memory bandwidth of this machine: a STREAM-like triad a = b + s c over arrays far larger than the caches
// (3 x 64 MiB), threaded with OpenMP like the library's loops. The figure the projection's memory-bound
// part is compared with (issue 6 quotes ~84 GB/s for its reference machine; this one is measured).
//   bench_bandwidth [--benchmark_filter=...]   (threads: OMP_NUM_THREADS, default all cores)
// Counter bytes_per_second counts 24 bytes per element (two reads, one write; write-allocate traffic
// not counted, as STREAM does). Results: benchmarks/RESULTS.md, section "Memory bandwidth".
#include <benchmark/benchmark.h>
#include <omp.h>

#include <vector>

namespace {

void BM_Triad(benchmark::State& state) {
  const long n = state.range(0);
  std::vector<double> a(static_cast<size_t>(n)), b(static_cast<size_t>(n)), c(static_cast<size_t>(n));
#pragma omp parallel for schedule(static)
  for (long i = 0; i < n; ++i) {  // first touch by the threads that use the pages
    a[static_cast<size_t>(i)] = 0.0;
    b[static_cast<size_t>(i)] = 1.0;
    c[static_cast<size_t>(i)] = 2.0;
  }
  const double s = 3.0;
  for (auto _ : state) {
    double* __restrict pa = a.data();
    const double* __restrict pb = b.data();
    const double* __restrict pc = c.data();
#pragma omp parallel for schedule(static)
    for (long i = 0; i < n; ++i) pa[i] = pb[i] + s * pc[i];
    benchmark::DoNotOptimize(a.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(state.iterations() * n * 24);
  state.counters["threads"] = omp_get_max_threads();
}

BENCHMARK(BM_Triad)->Arg(1 << 23)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
