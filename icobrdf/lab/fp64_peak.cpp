// The measured FP64 peak of icobrdf/lab/machine.hpp: an FMA-throughput loop compiled once per SIMD target (Highway
// foreach_target) and run on the target the kernels dispatch to (icobrdf/core/support/simd_target.hpp).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "icobrdf/lab/fp64_peak.cpp"
#include <hwy/foreach_target.h>  // re-includes this file once per target
#include <hwy/highway.h>

#include <cstdint>

#include "icobrdf/lab/machine.hpp"

HWY_BEFORE_NAMESPACE();
namespace icobrdf::lab {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// `iterations` steps of kFmaChains independent chains c = c m + b (one FMA per chain and step: the chains
// hide the FMA latency, 4 cycles x 2 pipes = 8 in flight on current x86 cores). With m = 1 - 2^-20 and
// b = 2^-20 each chain converges to 1 and never meets a denormal or an overflow. Returns the sum of the
// chains, so that the compiler keeps the loop.
double FmaChains(std::int64_t iterations) {
  const hn::ScalableTag<double> d;
  using V = hn::Vec<decltype(d)>;
  const V m = hn::Set(d, 1.0 - 0x1p-20), b = hn::Set(d, 0x1p-20);
  V c[kFmaChains];
#pragma GCC unroll 16
  for (int i = 0; i < kFmaChains; ++i) c[i] = hn::Set(d, 0.5 + 0.01 * i);
  for (std::int64_t it = 0; it < iterations; ++it) {
#pragma GCC unroll 16
    for (int i = 0; i < kFmaChains; ++i) c[i] = hn::MulAdd(c[i], m, b);
  }
  V s = c[0];
#pragma GCC unroll 16
  for (int i = 1; i < kFmaChains; ++i) s = hn::Add(s, c[i]);
  return hn::GetLane(hn::SumOfLanes(d, s));
}

}  // namespace HWY_NAMESPACE
}  // namespace icobrdf::lab
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
#include <omp.h>

#include <algorithm>

#include "icobrdf/core/support/simd_target.hpp"
#include "icobrdf/lab/timing.hpp"

namespace icobrdf::lab {

HWY_EXPORT(FmaChains);

namespace {
// Steps per thread and run: 2^23 steps x 12 chains x 8 lanes x 2 flops = 1.6 GFLOP per thread on AVX-512,
// about 12 ms on a 136 GFLOP/s core: long enough for a steady clock, short enough to repeat.
constexpr std::int64_t kFmaSteps = std::int64_t{1} << 23;
// Runs per measurement; the best is kept (the first also pays for thread start-up and clock ramp-up).
constexpr int kFmaRuns = 5;
}  // namespace

double measure_fp64_peak_gflops(int threads) {
  volatile double sink = 0.0;
  const double best = best_seconds(kFmaRuns, [&] {
    double total = 0.0;
#pragma omp parallel num_threads(threads) reduction(+ : total)
    total += HWY_DYNAMIC_DISPATCH(FmaChains)(kFmaSteps);
    sink = sink + total;
  });
  const double flops = 2.0 * kFmaChains * dispatched_f64_lanes() * static_cast<double>(kFmaSteps) * threads;
  return flops / best / 1e9;
}

}  // namespace icobrdf::lab
#endif
