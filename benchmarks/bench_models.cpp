// Batch evaluation of the analytic BRDF models (icobrdf/core/models/model_registry.hpp): f at 4096 random direction pairs per
// call (ModelEval), or one incident direction against 4096 remitted ones as in a LUT row (ModelEvalRow), one
// thread.   bench_models [--benchmark_filter=...]
// Results: benchmarks/RESULTS.md, section "Analytic BRDF models".
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "icobrdf/core/models/model_registry.hpp"

namespace {

using namespace icobrdf;

constexpr int kPairs = 4096;

RowMatrix3d random_directions(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  RowMatrix3d d(kPairs, 3);
  for (int k = 0; k < kPairs; ++k) {
    const double z = u(rng), s = std::sqrt(1.0 - z * z), p = 2.0 * M_PI * u(rng);
    d.row(k) << s * std::cos(p), s * std::sin(p), z;
  }
  return d;
}

// Times BrdfModel::eval of `spec` on the kPairs pairs (wi, wr).
void time_eval(benchmark::State& state, const std::string& spec, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  const auto model = parse_model(spec);
  Eigen::MatrixXd out(kPairs, model->channels());
  for (auto _ : state) {
    model->eval(wi, wr, out);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * kPairs);
}

void BM_ModelEval(benchmark::State& state, const std::string& spec) {
  std::mt19937_64 rng(5);
  const RowMatrix3d wi = random_directions(rng), wr = random_directions(rng);
  time_eval(state, spec, wi, wr);
}

// The pattern of a LUT row: one incident direction against every remitted one (models that cache per-direction
// factors, such as Beckmann's Smith term, compute the incident one once).
void BM_ModelEvalRow(benchmark::State& state, const std::string& spec) {
  std::mt19937_64 rng(5);
  const RowMatrix3d wr = random_directions(rng);
  time_eval(state, spec, wr.row(0).replicate(kPairs, 1), wr);
}

void BM_ParseModel(benchmark::State& state, const std::string& spec) {
  for (auto _ : state) {
    auto m = parse_model(spec);
    benchmark::DoNotOptimize(m.get());
  }
}

const int kRegistered = [] {
  for (const char* spec : {"lambert", "minnaert:k=2.5", "phong", "blinn-phong", "ggx", "ggx:fresnel=dielectric",
                           "beckmann", "ggx-aniso", "oren-nayar", "lafortune", "lommel-seeliger", "hapke",
                           "0.8*lambert+0.2*ggx:alpha=0.1"})
    benchmark::RegisterBenchmark(("ModelEval/" + std::string(spec)).c_str(), BM_ModelEval, std::string(spec));
  for (const char* spec : {"ggx", "beckmann"})
    benchmark::RegisterBenchmark(("ModelEvalRow/" + std::string(spec)).c_str(), BM_ModelEvalRow, std::string(spec));
  benchmark::RegisterBenchmark("ParseModel/hapke", BM_ParseModel, std::string("hapke"));
  benchmark::RegisterBenchmark("ParseModel/ggx", BM_ParseModel, std::string("ggx:alpha=0.2,f0=0.04"));
  return 0;
}();

}  // namespace

BENCHMARK_MAIN();
