// Half-angle factorized representation: evaluation speed (Google Benchmark) and, with --study, a table of
// fit time, rank, bytes and held-out cosine-metric error for glossy materials (isotropic; --aniso for the
// anisotropic one), and the h-warp comparison.
//   bench_half_angle [benchmark flags]       evaluation speed at random pairs
//   bench_half_angle --study                 materials x grids table
//   bench_half_angle --warp                  error per byte of the theta_h warps (GGX alpha 0.05/0.1/0.3)
//   bench_half_angle --grids                 held-out error against each grid size separately
//   bench_half_angle --extension             extension weight and rank against held-out error
//   bench_half_angle --aniso                 anisotropic GGX at a few grids
//   bench_half_angle --lut                   level-2 LUT of one lobe per stored form: seconds, evaluations, and
//                                            the degree-9 against the degree-2 cell averages
#include <benchmark/benchmark.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/fit/half_angle_fit.hpp"
#include "icobrdf/core/models/half_angle_factors.hpp"
#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/mesh/tessellation.hpp"

using namespace icobrdf;

namespace {

// Relative L2 error of q = f cos_i cos_r (channel 0) over held-out pairs.
double cosine_error(const BrdfModel& m, const HalfAngleFactors& F, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  Eigen::MatrixXd f(wi.rows(), 1), g(wi.rows(), F.channels());
  m.eval(wi, wr, f);
  F.eval_quantity(wi, wr, g);
  if (F.quantity == HalfAngleQuantity::F) g.col(0).array() *= wi.col(2).array() * wr.col(2).array();
  const Eigen::ArrayXd q = f.col(0).array() * wi.col(2).array() * wr.col(2).array();
  return std::sqrt((g.col(0).array() - q).square().sum() / q.square().sum());
}

// The lobes the glossy bank stores: mean-cosine quantity, corners below the horizon dropped; the anisotropic
// one on the stretched 48 x 16 h grid of GGX 0.1 x 0.3.
void BM_Eval(benchmark::State& state) {
  const bool aniso = state.range(1) != 0;
  const auto model = parse_model_source(aniso ? "model:ggx-aniso:alpha_x=0.1,alpha_y=0.3,f0=0.04" : "model:ggx:alpha=0.1,f0=0.04");
  HalfAngleFitOptions o;
  o.quantity = HalfAngleQuantity::MeanCosine;
  o.n_t = aniso ? 48 : 64;
  o.n_theta_d = 64;
  o.n_phi_d = 16;
  o.isotropic = !aniso;
  o.n_phi_h = 16;
  o.h_axis = M_PI / 2, o.h_scale_1 = aniso ? 3.3 : 1.0;
  o.fixed_rank = static_cast<int>(state.range(0));
  const auto fit = fit_half_angle(model_pair_sampler(*model), 1, o);
  RowMatrix3d wi, wr;
  uniform_pairs(1 << 20, 7, wi, wr);
  Eigen::MatrixXd out(wi.rows(), 1);
  for (auto _ : state) {
    fit.factors.eval(wi, wr, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(state.iterations() * wi.rows());
}
BENCHMARK(BM_Eval)->ArgsProduct({{1, 2, 4}, {0, 1}})->ArgNames({"rank", "aniso"})->Unit(benchmark::kMillisecond)->UseRealTime();

struct Material {
  const char* spec;
  bool isotropic;
};

void study() {
  RowMatrix3d wi, wr;
  uniform_pairs(20000, 20251124, wi, wr);
  const Material mats[] = {{"ggx:alpha=0.3,f0=0.04", true},   {"ggx:alpha=0.2,f0=0.04", true},
                           {"ggx:alpha=0.1,f0=0.04", true},   {"ggx:alpha=0.05,f0=0.04", true},
                           {"ggx:alpha=0.1,f0=0.9", true},    {"beckmann:alpha=0.1,f0=0.04", true},
                           {"0.8*lambert+0.2*ggx:alpha=0.1", true}, {"0.7*lambert+0.3*blinn-phong:n=200", true}};
  struct G {
    int nt, nph, ntd, npd;
  };
  const G grids[] = {{32, 1, 32, 16}, {64, 1, 64, 16}, {96, 1, 96, 16}};
  std::printf("%-36s %4s %4s %4s %4s %5s %9s %9s %9s %8s %s\n", "material", "n_t", "n_ph", "n_td", "n_pd", "rank",
              "bytes", "node_err", "heldout", "seconds", "sweeps");
  for (const auto& m : mats) {
    const auto model = parse_model(m.spec);
    for (const auto& g : grids) {
      HalfAngleFitOptions o;
      o.isotropic = m.isotropic;
      o.n_t = g.nt;
      o.n_phi_h = g.nph;
      o.n_theta_d = g.ntd;
      o.n_phi_d = g.npd;
      o.target = 0.01;
      o.max_rank = 8;
      try {
        const auto fit = fit_half_angle(model_pair_sampler(*model), 1, o);
        std::string sw;
        for (int s : fit.report.sweeps_by_rank) sw += std::to_string(s) + " ";
        std::printf("%-36s %4d %4d %4d %4d %5d %9zu %9.2e %9.2e %8.3f %s\n", m.spec, g.nt, fit.factors.n_phi_h, g.ntd,
                    g.npd, fit.report.rank, fit.factors.bytes(), fit.report.error[0],
                    cosine_error(*model, fit.factors, wi, wr), fit.report.seconds, sw.c_str());
      } catch (const UnsupportedError& e) {
        std::printf("%-36s %4d %4d %4d %4d  refused: %s\n", m.spec, g.nt, g.nph, g.ntd, g.npd, e.what());
      }
      std::fflush(stdout);
    }
  }
}

void warp_study() {
  RowMatrix3d wi, wr;
  uniform_pairs(20000, 99, wi, wr);
  std::printf("%-24s %5s %4s %4s %9s %9s %9s\n", "material", "warp", "n_t", "rank", "bytes", "node_err", "heldout");
  for (const char* spec : {"ggx:alpha=0.05,f0=0.04", "ggx:alpha=0.1,f0=0.04", "ggx:alpha=0.3,f0=0.04"}) {
    const auto model = parse_model(spec);
    for (double warp : {1.0, 2.0, 3.0})
      for (int nt : {12, 16, 24, 32, 64}) {
        HalfAngleFitOptions o;
        o.h_warp = warp;
        o.n_t = nt;
        o.fixed_rank = 3;
        const auto fit = fit_half_angle(model_pair_sampler(*model), 1, o);
        std::printf("%-24s %5.1f %4d %4d %9zu %9.2e %9.2e\n", spec, warp, nt, fit.report.rank, fit.factors.bytes(),
                    fit.report.error[0], cosine_error(*model, fit.factors, wi, wr));
        std::fflush(stdout);
      }
  }
}

// Held-out error against each grid size separately (GGX alpha 0.1 and 0.3, rank 3).
void grid_study() {
  RowMatrix3d wi, wr;
  uniform_pairs(20000, 5, wi, wr);
  std::printf("%-24s %4s %4s %4s %9s %9s %9s %8s\n", "material", "n_t", "n_td", "n_pd", "bytes", "node_err", "heldout",
              "seconds");
  for (const char* spec : {"ggx:alpha=0.1,f0=0.04", "ggx:alpha=0.3,f0=0.04"}) {
    const auto model = parse_model(spec);
    for (const auto& g : std::vector<std::array<int, 3>>{
             {64, 32, 16}, {128, 32, 16}, {64, 64, 16}, {64, 32, 32}, {64, 32, 8}, {96, 64, 16}, {128, 64, 16}}) {
      HalfAngleFitOptions o;
      o.n_t = g[0];
      o.n_theta_d = g[1];
      o.n_phi_d = g[2];
      o.fixed_rank = 3;
      const auto fit = fit_half_angle(model_pair_sampler(*model), 1, o);
      std::printf("%-24s %4d %4d %4d %9zu %9.2e %9.2e %8.3f\n", spec, g[0], g[1], g[2], fit.factors.bytes(),
                  fit.report.error[0], cosine_error(*model, fit.factors, wi, wr), fit.report.seconds);
      std::fflush(stdout);
    }
  }
}

// Extension weight and rank against held-out error (GGX alpha 0.1, grid 64/64/16).
void extension_study() {
  RowMatrix3d wi, wr;
  uniform_pairs(20000, 6, wi, wr);
  const auto model = parse_model("ggx:alpha=0.1,f0=0.04");
  for (double ew : {0.0, 0.05, 0.3, 1.0})
    for (int r : {2, 3, 4}) {
      HalfAngleFitOptions o;
      o.n_t = 64;
      o.n_theta_d = 64;
      o.n_phi_d = 16;
      o.fixed_rank = r;
      o.extension_weight = ew;
      const auto fit = fit_half_angle(model_pair_sampler(*model), 1, o);
      std::string sw;
      for (int s : fit.report.sweeps_by_rank) sw += std::to_string(s) + " ";
      std::printf("ext %5.2f rank %d node_err %9.2e heldout %9.2e seconds %7.3f sweeps %s\n", ew, r,
                  fit.report.error[0], cosine_error(*model, fit.factors, wi, wr), fit.report.seconds, sw.c_str());
      std::fflush(stdout);
    }
}

// Anisotropic GGX 0.1/0.3 at a few grids (target 0.01).
void aniso_study(std::size_t first) {
  RowMatrix3d wi, wr;
  uniform_pairs(20000, 8, wi, wr);
  const auto model = parse_model("ggx-aniso:alpha_x=0.1,alpha_y=0.3");
  const std::vector<std::array<int, 4>> grids{{32, 16, 48, 16}, {48, 32, 48, 16}, {48, 16, 64, 16}, {64, 32, 64, 16}, {48, 64, 48, 16}, {32, 64, 64, 16}};
  for (std::size_t k = first; k < grids.size(); ++k) {
    const auto& g = grids[k];
    HalfAngleFitOptions o;
    o.isotropic = false;
    o.n_t = g[0], o.n_phi_h = g[1], o.n_theta_d = g[2], o.n_phi_d = g[3];
    o.max_rank = 16;
    o.sweep_tolerance = 1e-4;
    try {
      const auto fit = fit_half_angle(model_pair_sampler(*model), 1, o);
      std::string sw;
      for (int s : fit.report.sweeps_by_rank) sw += std::to_string(s) + " ";
      std::printf("aniso %d %d %d %d rank %d bytes %zu node_err %.2e heldout %.2e seconds %.2f sweeps %s\n", g[0], g[1], g[2],
                  g[3], fit.report.rank, fit.factors.bytes(), fit.report.error[0], cosine_error(*model, fit.factors, wi, wr),
                  fit.report.seconds, sw.c_str());
    } catch (const UnsupportedError& e) {
      std::printf("aniso %d %d %d %d refused: %s\n", g[0], g[1], g[2], g[3], e.what());
    }
    std::fflush(stdout);
  }
}

}  // namespace


// The LUT of a lobe on the level-2 bank grid (cell averages with the grid's cubature) per stored form of the
// same fitted factors: float64 per channel, then each narrower precision (quantize()), and shared factors. A
// stored form changes the values, never the work: every form's LUT should take the float64 one's time. Also
// prints the evaluations a LUT costs and how far cell averages with the cheap degree-2 rule fall from the
// degree-9 ones.
void lut_study() {
  struct Lobe {
    const char* spec;
    bool isotropic;
    int channels;
  };
  const Lobe lobes[] = {{"model:oren-nayar:sigma=30,albedo=0.7", false, 1}, {"model:ggx:alpha=0.3,f0=0.04", true, 1}};
  for (const int degree : {kDefaultCubatureDegree, kLutSamplingDegree}) {
    const Grid g = build_equal_area_grid(2, degree);
    std::printf("level 2, cubature degree %d: %d cells, %lld points, %.3g evaluations per LUT\n", degree, g.cells(),
                static_cast<long long>(g.cubature_weights.size()),
                static_cast<double>(g.cubature_weights.size()) * static_cast<double>(g.cubature_weights.size()));
  }
  const Grid grid = build_equal_area_grid(2);
  for (const Lobe& l : lobes) {
    const auto model = parse_model_source(l.spec);
    HalfAngleFitOptions o;
    o.quantity = HalfAngleQuantity::MeanCosine;
    o.isotropic = l.isotropic;
    o.n_t = 32, o.n_phi_h = l.isotropic ? 1 : 8, o.n_theta_d = 64, o.n_phi_d = 16;
    o.fixed_rank = 2;
    const HalfAngleFactors base = fit_half_angle(model_pair_sampler(*model), l.channels, o).factors;
    const auto lut_of = [](const HalfAngleFactors& F, const Grid& on, double& seconds) {
      const FunctionModel m(
          F.channels(), [&F](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) { F.eval(wi, wr, out); },
          "lobe", F.isotropic, true);
      const auto t0 = std::chrono::steady_clock::now();
      Lut lut = build_lut(m, on, false);
      seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return lut.channels[0];
    };
    double t64 = 0.0;
    const Eigen::MatrixXd f64 = lut_of(base, grid, t64);
    std::printf("%s (%s, rank 2): float64 %.2f s\n", l.spec, l.isotropic ? "isotropic" : "anisotropic", t64);
    for (const FactorPrecision p : {FactorPrecision::Float32, FactorPrecision::Int16, FactorPrecision::Int8}) {
      HalfAngleFactors q = base;
      q.precision = p;
      q.quantize();
      double t = 0.0;
      const Eigen::MatrixXd fq = lut_of(q, grid, t);
      std::printf("  %-7s %.2f s (%.2fx float64), LUT relative difference %.2e\n", factor_precision_name(p), t, t / t64,
                  (fq - f64).norm() / f64.norm());
    }
    for (const int degree : {2, 3, 4, 5, 6, 7}) {
      double tc = 0.0;
      const Eigen::MatrixXd fc = lut_of(base, build_equal_area_grid(2, degree), tc);
      std::printf("  degree-%d cell averages: %.2f s, relative difference from degree 9 %.2e\n", degree, tc, (fc - f64).norm() / f64.norm());
    }
  }
}

int main(int argc, char** argv) {
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--study") == 0) return study(), 0;
    if (std::strcmp(argv[k], "--warp") == 0) return warp_study(), 0;
    if (std::strcmp(argv[k], "--grids") == 0) return grid_study(), 0;
    if (std::strcmp(argv[k], "--extension") == 0) return extension_study(), 0;
    if (std::strcmp(argv[k], "--lut") == 0) return lut_study(), 0;
    if (std::strcmp(argv[k], "--aniso") == 0) return aniso_study(k + 1 < argc ? std::stoul(argv[k + 1]) : 0), 0;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
