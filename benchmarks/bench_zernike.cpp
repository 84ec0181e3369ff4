// Zernike radial polynomials and batch mode evaluation.
//   bench_zernike --benchmark_filter=Zernike    all R_n^l, n <= N, at one rho: recurrence vs closed sum (eq. 3)
//   bench_zernike --benchmark_filter=Eval       K / Helmholtz / isotropic values at 1000 directions (pairs)
// Results: benchmarks/RESULTS.md, section "Zernike and mode evaluation".
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/basis/zernike.hpp"

namespace {

using namespace icobrdf;

void BM_ZernikeRecurrence(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  std::vector<double> out(static_cast<size_t>(zernike_radial_count(order)));
  double rho = 0.3;
  for (auto _ : state) {
    zernike_radial_all(order, rho, out.data());
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    rho = rho < 0.99 ? rho + 1e-3 : 0.3;
  }
  state.counters["polys"] = static_cast<double>(out.size());
}

// Baseline: the closed factorial sum (eq. 3) for every (n, l), with a precomputed factorial table and the
// powers of rho computed once per call. (Inaccurate beyond n ~ 40; timing only.)
void BM_ZernikeClosedSum(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  std::vector<double> fact(static_cast<size_t>(order + 1), 1.0), pw(static_cast<size_t>(order + 1));
  for (int i = 1; i <= order; ++i) fact[static_cast<size_t>(i)] = fact[static_cast<size_t>(i - 1)] * i;
  std::vector<double> out(static_cast<size_t>(zernike_radial_count(order)));
  double rho = 0.3;
  for (auto _ : state) {
    pw[0] = 1.0;
    for (int i = 1; i <= order; ++i) pw[static_cast<size_t>(i)] = pw[static_cast<size_t>(i - 1)] * rho;
    size_t k = 0;
    for (int n = 0; n <= order; ++n)
      for (int l = n % 2; l <= n; l += 2) {
        double sum = 0.0;
        for (int s = 0; s <= (n - l) / 2; ++s) {
          const double c = fact[static_cast<size_t>(n - s)] /
                           (fact[static_cast<size_t>(s)] * fact[static_cast<size_t>((n + l) / 2 - s)] *
                            fact[static_cast<size_t>((n - l) / 2 - s)]);
          sum += (s % 2 ? -c : c) * pw[static_cast<size_t>(n - 2 * s)];
        }
        out[k++] = sum;
      }
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
    rho = rho < 0.99 ? rho + 1e-3 : 0.3;
  }
}

RowMatrix3d random_dirs(int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0), ph(-M_PI, M_PI);
  RowMatrix3d d(count, 3);
  for (int r = 0; r < count; ++r) {
    const double z = u(rng), s = std::sqrt(1 - z * z), phi = ph(rng);  // uniform in solid angle
    d.row(r) << s * std::cos(phi), s * std::sin(phi), z;
  }
  return d;
}

constexpr int kRows = 1000;

void BM_EvalHemisphereBasis(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const RowMatrix3d d = random_dirs(kRows, 1);
  for (auto _ : state) benchmark::DoNotOptimize(hemisphere_basis_matrix(order, d).data());
  state.SetItemsProcessed(state.iterations() * kRows);  // directions
  state.counters["values"] = static_cast<double>(kRows) * hemisphere_basis_count(order);
}

void BM_EvalHelmholtzModes(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const RowMatrix3d wi = random_dirs(kRows, 2), wr = random_dirs(kRows, 3);
  for (auto _ : state) benchmark::DoNotOptimize(helmholtz_modes_eval(order, wi, wr).data());
  state.SetItemsProcessed(state.iterations() * kRows);  // direction pairs
  state.counters["values"] = static_cast<double>(kRows) * static_cast<double>(helmholtz_mode_count(order));
}

void BM_EvalIsotropicModes(benchmark::State& state) {
  const int order = static_cast<int>(state.range(0));
  const RowMatrix3d wi = random_dirs(kRows, 4), wr = random_dirs(kRows, 5);
  for (auto _ : state) benchmark::DoNotOptimize(isotropic_modes_eval(order, wi, wr).data());
  state.SetItemsProcessed(state.iterations() * kRows);
  state.counters["values"] = static_cast<double>(kRows) * isotropic_mode_count(order);
}

}  // namespace

BENCHMARK(BM_ZernikeRecurrence)->Arg(16)->Arg(32)->Arg(64)->Arg(128);
BENCHMARK(BM_ZernikeClosedSum)->Arg(16)->Arg(32)->Arg(64)->Arg(128);
BENCHMARK(BM_EvalHemisphereBasis)->Arg(8)->Arg(16)->Arg(64)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EvalHelmholtzModes)->Arg(4)->Arg(8)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EvalIsotropicModes)->Arg(8)->Arg(16)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
