// Importance sampling (icobrdf/io/material_sampler.hpp), single thread, GGX alpha 0.3 at theta_i = 40 deg.
//   BM_Distribution/L     building the distribution of one w_i at level L (f at every cell; average: at every
//                         cubature point); items_per_second = distributions per second
//   BM_Sample/L           draws from a built distribution, with f evaluated at each draw for the weight;
//                         items_per_second = samples per second (2^16 per call)
//   BM_DrawOnly/L         the same without f: CDF search, uniform point in the cell, inverse Snyder map
//   BM_Pdf/L              pdf() at random directions (cell lookup + division)
#include <benchmark/benchmark.h>

#include <random>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/io/material_sampler.hpp"

namespace {

using namespace icobrdf;
constexpr int kDraws = 1 << 16;

const Eigen::Vector3d& incident() {
  static const Eigen::Vector3d wi = direction_from_angles(40 * M_PI / 180, 0.0);
  return wi;
}

// A sampler of `level`, the distribution of incident(), and kDraws pairs of uniform numbers.
struct Setup {
  MaterialSampler s;
  IncidentDistribution d;
  Eigen::VectorXd u1, u2;
  explicit Setup(int level) : s(open_source("model:ggx:alpha=0.3"), level), d(s.distribution(incident())), u1(kDraws), u2(kDraws) {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < kDraws; ++i) u1[i] = u(rng), u2[i] = u(rng);
  }
};

void BM_Distribution(benchmark::State& state, LutSampling mode) {
  const MaterialSampler s(open_source("model:ggx:alpha=0.3"), static_cast<int>(state.range(0)), mode);
  for (auto _ : state) {
    const IncidentDistribution d = s.distribution(incident());
    benchmark::DoNotOptimize(d.albedo_estimate);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(BM_Distribution, centre, LutSampling::CellCentre)->Arg(3)->Arg(5)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Distribution, average, LutSampling::CellAverage)->Arg(5)->Unit(benchmark::kMillisecond);

void BM_Sample(benchmark::State& state) {
  const Setup x(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const MaterialSamples m = x.s.sample(x.d, x.u1, x.u2);
    benchmark::DoNotOptimize(m.weight.data());
  }
  state.SetItemsProcessed(state.iterations() * kDraws);
}
BENCHMARK(BM_Sample)->Arg(3)->Arg(5)->Arg(7);

void BM_DrawOnly(benchmark::State& state) {
  const Setup x(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    double acc = 0;
    for (int i = 0; i < kDraws; ++i) acc += x.s.directions().sample(x.d.cells, x.u1[i], x.u2[i]).pdf;
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(state.iterations() * kDraws);
}
BENCHMARK(BM_DrawOnly)->Arg(5);

void BM_Pdf(benchmark::State& state) {
  const Setup x(static_cast<int>(state.range(0)));
  RowMatrix3d wr(kDraws, 3);  // uniform in solid angle
  for (int i = 0; i < kDraws; ++i) {
    const double z = x.u1[i], phi = 2 * M_PI * x.u2[i], st = std::sqrt(1 - z * z);
    wr.row(i) << st * std::cos(phi), st * std::sin(phi), z;
  }
  for (auto _ : state) {
    const Eigen::VectorXd p = x.s.pdf(x.d, wr);
    benchmark::DoNotOptimize(p.data());
  }
  state.SetItemsProcessed(state.iterations() * kDraws);
}
BENCHMARK(BM_Pdf)->Arg(5);

}  // namespace

BENCHMARK_MAIN();
