// Readers of measured data: MERL table I/O and the sample fits behind `icobrdf fit FILE.binary|FILE.csv`.
//   bench_readers --benchmark_filter=Merl        write (from a model), read + validate, node samples, fit
//   bench_readers --benchmark_filter=SampleFit   scattered-sample fit: general / isotropic modes
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <cmath>
#include <random>
#include <string>

#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/fit/sample_fit.hpp"
#include "icobrdf/io/merl.hpp"

namespace {

using namespace icobrdf;

std::string merl_path() {
  static const std::string path = [] {
    const std::string p = "/tmp/icobrdf_bench_readers_" + std::to_string(::getpid()) + ".binary";
    write_merl(p, *parse_model("ggx:alpha=0.3"));
    return p;
  }();
  return path;
}

void BM_MerlWrite(benchmark::State& state) {
  const auto model = parse_model("ggx:alpha=0.3");
  const std::string p = merl_path() + ".w";
  for (auto _ : state) write_merl(p, *model);
  ::unlink(p.c_str());
}
BENCHMARK(BM_MerlWrite)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_MerlRead(benchmark::State& state) {
  const std::string p = merl_path();
  for (auto _ : state) benchmark::DoNotOptimize(read_merl(p).f.data());
}
BENCHMARK(BM_MerlRead)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_MerlSamples(benchmark::State& state) {
  const MerlTable t = read_merl(merl_path());
  for (auto _ : state) benchmark::DoNotOptimize(merl_samples(t).weights.data());
}
BENCHMARK(BM_MerlSamples)->Unit(benchmark::kMillisecond)->Iterations(2);

void BM_MerlFit(benchmark::State& state) {
  const MerlSamples s = merl_samples(read_merl(merl_path()));
  SampleFitOptions o;
  o.order = static_cast<int>(state.range(0));
  o.isotropic = true;
  for (auto _ : state) benchmark::DoNotOptimize(fit_samples(s.wi, s.wr, s.values, s.weights, o).modes.data());
  state.counters["samples"] = static_cast<double>(s.wi.rows());
}
BENCHMARK(BM_MerlFit)->Arg(4)->Arg(8)->Unit(benchmark::kMillisecond)->Iterations(1);

void BM_SampleFit(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const bool iso = state.range(1) != 0;
  const int n = 5000;
  std::mt19937 g(1);
  std::uniform_real_distribution<double> u(0, 1);
  RowMatrix3d wi(n, 3), wr(n, 3);
  for (int r = 0; r < n; ++r)
    for (auto* m : {&wi, &wr}) {
      const double z = u(g), p = 2 * M_PI * u(g), s = std::sqrt(1 - z * z);
      m->row(r) << s * std::cos(p), s * std::sin(p), z;
    }
  const Eigen::VectorXd y = Eigen::VectorXd::Ones(n);
  SampleFitOptions o;
  o.order = order;
  o.isotropic = iso;
  for (auto _ : state) benchmark::DoNotOptimize(fit_samples(wi, wr, y, Eigen::VectorXd(), o).modes.data());
  state.counters["unknowns"] = iso ? isotropic_mode_count(order) : static_cast<double>(helmholtz_mode_count(order));
}
BENCHMARK(BM_SampleFit)->Args({4, 0})->Args({6, 0})->Args({8, 1})->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
