// Per-sample calls of a renderer-facing material (icobrdf/io/render_material.hpp), one thread unless noted:
//   BM_Eval<Real>/M     eval(w_i, w_r) at 4096 random pairs in turn; items_per_second = calls per second
//   BM_Pdf<Real>/M      pdf(w_i, w_r) at the same pairs
//   BM_Sample<Real>/M   sample(w_i, u1, u2) at 4096 random incident directions and numbers in turn
//   BM_Build/M          building the material (tables over the incident direction)
//   BM_ClockReference   a chain of dependent integer adds, one per cycle (x86-64): items_per_second is the
//                       core's clock in this run, so that the calls' times can be read in cycles (the host's
//                       clock was seen to move between 1.7 and 2.9 GHz within an hour)
// On x86-64 the per-call benchmarks also report the counter cycles: the loop's wall time per call times the
// clock the same chain of adds measures just before and just after the loop (their mean), so that a figure
// taken while the host runs slow or fast reads the same in cycles (a target of 100 ns is 280 cycles at 2.8 GHz
// and 180 at 1.8 GHz).
// Materials M: 0 a half-angle lobe (rank <= 4, fitted to GGX alpha 0.3: a bank's half-angle representation),
// 1 the GGX alpha 0.3 model, 2 model 0.5*lambert+0.5*mirror (a delta part), 3 the lobe of 0 with tables that
// store every phi_h bin (HalfVectorTableOptions::mirror = false: twice the memory of 0's), 4 the lobe of 0 beside
// modes of order 0 (a constant: a bank's paint, its Lambertian part as modes), 5 the lobe of 0 beside modes of
// order 4 (a hybrid's body: Minnaert's k = 3, 15 modes). ->Threads(2) shares one material.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/fit/half_angle_fit.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/spectrum/analytic_spectra.hpp"
#include "icobrdf/io/render_material.hpp"

namespace {

using namespace icobrdf;
constexpr int kPairs = 4096;

Spectrum no_modes() {
  Spectrum s;
  s.order = 0;
  s.isotropic = true;
  s.channels = {Eigen::MatrixXd::Zero(1, 1)};
  s.source = "half-angle lobe";
  return s;
}

const HalfAngleFactors& lobe() {
  static const HalfAngleFactors l = [] {
    const auto m = parse_model_source("model:ggx:alpha=0.3");
    HalfAngleFitOptions o;
    o.max_rank = 4;
    o.target = 0.02;
    return fit_half_angle(model_pair_sampler(*m), 1, o).factors;
  }();
  return l;
}

RenderMaterial make(int which) {
  if (which == 0) return RenderMaterial(no_modes(), lobe());
  if (which == 4) {
    Spectrum constant = no_modes();
    constant.channels[0](0, 0) = 0.2;  // f = 0.2 K_0^2 = 0.2 / (2 pi) beside the lobe
    return RenderMaterial(constant, lobe());
  }
  if (which == 5) {
    Spectrum body = no_modes();
    body.order = 4;
    body.channels = {0.5 * minnaert_coefficients(4, 3)};
    return RenderMaterial(body, lobe());
  }
  if (which == 3) {
    RenderMaterialOptions full;
    full.table.mirror = false;
    return RenderMaterial(no_modes(), lobe(), full);
  }
  return RenderMaterial::open(which == 1 ? "model:ggx:alpha=0.3" : "model:0.5*lambert+0.5*mirror");
}

const RenderMaterial& material(int which) {
  static const std::vector<std::shared_ptr<RenderMaterial>> all = [] {
    std::vector<std::shared_ptr<RenderMaterial>> v;
    for (int i = 0; i < 6; ++i) v.push_back(std::make_shared<RenderMaterial>(make(i)));
    return v;
  }();
  return *all[static_cast<size_t>(which)];
}

template <class Real>
struct Inputs {
  std::vector<Eigen::Matrix<Real, 3, 1>> wi, wr;
  std::vector<Real> u1, u2;
  Inputs() {
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < kPairs; ++i) {
      wi.push_back(direction_from_angles(std::acos(u(rng)), 2 * M_PI * u(rng)).cast<Real>());
      wr.push_back(direction_from_angles(std::acos(u(rng)), 2 * M_PI * u(rng)).cast<Real>());
      u1.push_back(static_cast<Real>(u(rng)));
      u2.push_back(static_cast<Real>(u(rng)));
    }
  }
};

template <class Real>
const Inputs<Real>& inputs() {
  static const Inputs<Real> in;
  return in;
}

#if defined(__x86_64__)
// n dependent integer adds: n cycles of the core.
void dependent_adds(int n) {
  std::uint64_t x = 0;
  for (int i = 0; i < n; ++i) asm volatile("add $1, %0" : "+r"(x));  // each add waits for the last
  benchmark::DoNotOptimize(x);
}

// The core's clock [GHz] by chains of 2^19 dependent adds, timed by the steady clock: the fastest of 3 (a chain
// the host interrupts reads slow).
double clock_ghz() {
  constexpr int kAdds = 1 << 19;
  double best = 0.0;
  for (int run = 0; run < 3; ++run) {
    const auto t0 = std::chrono::steady_clock::now();
    dependent_adds(kAdds);
    best = std::max(best, kAdds / std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}
#else
double clock_ghz() { return 0.0; }
#endif

// Runs call() once per iteration and reports the counter cycles (see the top of this file) where the clock is known.
template <class Call>
void timed_calls(benchmark::State& state, Call call) {
  const double g0 = clock_ghz();
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) call();
  const double ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
  const double g1 = clock_ghz();
  if (g0 > 0.0 && g1 > 0.0 && state.iterations() > 0)
    state.counters["cycles"] = benchmark::Counter(ns / static_cast<double>(state.iterations()) * 0.5 * (g0 + g1),
                                                  benchmark::Counter::kAvgThreads);  // threads: each one's own
}

template <class Real>
void BM_Eval(benchmark::State& state) {
  const RenderMaterial& m = material(static_cast<int>(state.range(0)));
  const Inputs<Real>& in = inputs<Real>();
  int i = 0;
  timed_calls(state, [&] {
    benchmark::DoNotOptimize(m.eval(in.wi[static_cast<size_t>(i)], in.wr[static_cast<size_t>(i)]));
    i = (i + 1) & (kPairs - 1);
  });
  state.SetItemsProcessed(state.iterations());
}

template <class Real>
void BM_Pdf(benchmark::State& state) {
  const RenderMaterial& m = material(static_cast<int>(state.range(0)));
  const Inputs<Real>& in = inputs<Real>();
  int i = 0;
  timed_calls(state, [&] {
    benchmark::DoNotOptimize(m.pdf(in.wi[static_cast<size_t>(i)], in.wr[static_cast<size_t>(i)]));
    i = (i + 1) & (kPairs - 1);
  });
  state.SetItemsProcessed(state.iterations());
}

template <class Real>
void BM_Sample(benchmark::State& state) {
  const RenderMaterial& m = material(static_cast<int>(state.range(0)));
  const Inputs<Real>& in = inputs<Real>();
  int i = 0;
  timed_calls(state, [&] {
    benchmark::DoNotOptimize(m.sample(in.wi[static_cast<size_t>(i)], in.u1[static_cast<size_t>(i)], in.u2[static_cast<size_t>(i)]));
    i = (i + 1) & (kPairs - 1);
  });
  state.SetItemsProcessed(state.iterations());
}

void BM_Build(benchmark::State& state) {
  lobe();
  for (auto _ : state) benchmark::DoNotOptimize(make(static_cast<int>(state.range(0))));
  state.SetItemsProcessed(state.iterations());
}

#if defined(__x86_64__)
void BM_ClockReference(benchmark::State& state) {
  constexpr int kAdds = 1 << 20;
  for (auto _ : state) dependent_adds(kAdds);
  state.SetItemsProcessed(state.iterations() * kAdds);
}
BENCHMARK(BM_ClockReference);
#endif

BENCHMARK_TEMPLATE(BM_Eval, double)->DenseRange(0, 2)->Arg(4)->Arg(5);
BENCHMARK_TEMPLATE(BM_Eval, float)->DenseRange(0, 2)->Arg(4)->Arg(5);
BENCHMARK_TEMPLATE(BM_Pdf, double)->DenseRange(0, 2);
BENCHMARK_TEMPLATE(BM_Pdf, float)->DenseRange(0, 2);
BENCHMARK_TEMPLATE(BM_Sample, double)->DenseRange(0, 5);
BENCHMARK_TEMPLATE(BM_Sample, float)->DenseRange(0, 5);
BENCHMARK_TEMPLATE(BM_Sample, double)->Arg(0)->Threads(2);
BENCHMARK(BM_Build)->DenseRange(0, 3)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
