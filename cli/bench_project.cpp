// icobrdf bench project --level L --order N [--threads T] [--repeat R] [--peak-gflops G] [--json]
// Times one projection C = P^T F P of a cells x cells LUT (the large GEMM dominates: 2 cells^2 modes flops)
// with the library's call (core/projection.hpp, Eigen) and with raw OpenBLAS doing the same products in the
// same run (in both association orders, the faster being the baseline), and
// reports GFLOP/s, the ratio to the machine's FP64 peak and to the BLAS baseline.
// Peak = threads x (FP64 flops per cycle per core of the instruction set compiled for: 32 with AVX-512,
// 16 with AVX2 + FMA, 8 with AVX, 4 otherwise) x clock (the first "cpu MHz" of /proc/cpuinfo, or --peak-gflops).
#include <cblas.h>
#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <fstream>
#include <iostream>
#include <random>

#include "cli/bench_commands.hpp"
#include "cli/machine.hpp"
#include "core/discrete_basis.hpp"
#include "core/error.hpp"
#include "core/projection.hpp"
#include "mesh/tessellation.hpp"

namespace icobrdf::cli {
namespace {

struct BenchArgs {
  int level = 5, order = 8, threads = 0, repeat = 5;
  double peak_gflops = 0.0;
  bool json = false;
};

template <class F>
double best_seconds(int repeat, F&& f) {
  double best = 1e300;
  for (int k = 0; k < repeat; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

void run_project(const BenchArgs& a) {
  const int threads = a.threads > 0 ? a.threads : omp_get_num_procs();
  omp_set_num_threads(threads);
  Eigen::setNbThreads(threads);
  openblas_set_num_threads(threads);
  const Grid g = with_centre_cubature(build_equal_area_grid(a.level));
  const auto basis = build_discrete_basis(g, a.order);
  check_supported(basis);
  const auto proj = make_projection(basis);
  const Eigen::Index c = g.cells(), m = proj.P.cols();
  // A dense LUT of random values, written once so its pages are resident before timing.
  Eigen::MatrixXd f(c, c);
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (Eigen::Index k = 0; k < f.size(); ++k) f.data()[k] = u(rng);
  Eigen::MatrixXd out(m, m), fp_blas(c, m), pf_blas(m, c), out_blas(m, m);
  // The library's own call (core/projection.hpp).
  const double ours = best_seconds(a.repeat, [&] { out = project_lut(proj, f); });
  // Raw OpenBLAS, column-major as Eigen stores, in both association orders; the faster is the baseline.
  const int ci = static_cast<int>(c), mi = static_cast<int>(m);
  const double blas_fp = best_seconds(a.repeat, [&] {  // (F P), then P^T (F P)
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, ci, mi, ci, 1.0, f.data(), ci, proj.P.data(), ci, 0.0, fp_blas.data(), ci);
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, mi, mi, ci, 1.0, proj.P.data(), ci, fp_blas.data(), ci, 0.0, out_blas.data(), mi);
  });
  const double blas_pf = best_seconds(a.repeat, [&] {  // (P^T F), then (P^T F) P
    cblas_dgemm(CblasColMajor, CblasTrans, CblasNoTrans, mi, ci, ci, 1.0, proj.P.data(), ci, f.data(), ci, 0.0, pf_blas.data(), mi);
    cblas_dgemm(CblasColMajor, CblasNoTrans, CblasNoTrans, mi, mi, ci, 1.0, pf_blas.data(), mi, proj.P.data(), ci, 0.0, out_blas.data(), mi);
  });
  const double blas = std::min(blas_fp, blas_pf);
  const double agree = (out - out_blas).cwiseAbs().maxCoeff() / std::max(1e-300, out.cwiseAbs().maxCoeff());
  const double flops = 2.0 * c * c * m + 2.0 * c * m * m;
  const double gflops = flops / ours / 1e9;
  const double peak = a.peak_gflops > 0 ? a.peak_gflops : fp64_peak_gflops(threads);
  nlohmann::json j{{"level", a.level},      {"order", a.order},          {"cells", c},
                   {"modes", m},            {"threads", threads},        {"seconds", ours},
                   {"gflops", gflops},      {"peak_gflops", peak},       {"peak_ratio", peak > 0 ? gflops / peak : 0.0},
                   {"blas_seconds", blas},  {"blas_ratio", blas / ours}, {"blas_gflops", flops / blas / 1e9},
                   {"flops_per_cycle_per_core", flops_per_cycle_per_core()}, {"cpu_mhz", cpu_mhz()},
                   {"relative_difference_to_blas", agree}, {"blas", "OpenBLAS (cblas_dgemm), faster of (F P) and (P^T F) first"},
                   {"blas_seconds_fp_first", blas_fp}, {"blas_seconds_pf_first", blas_pf},
                   {"eigen_simd", Eigen::SimdInstructionSetsInUse()}};
  if (a.json) {
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << fmt::format("projection C = P^T F P, level {} ({} cells), order {} ({} modes), {} thread(s)\n", a.level, c, a.order, m, threads)
            << fmt::format("  icobrdf (Eigen): {:.4f} s, {:.1f} GFLOP/s = {:.0f}% of the FP64 peak {:.1f} GFLOP/s\n", ours, gflops,
                           100 * gflops / peak, peak)
            << fmt::format("  raw OpenBLAS:    {:.4f} s, {:.1f} GFLOP/s; icobrdf is {:.2f}x its speed (results agree to {:.1e})\n", blas,
                           flops / blas / 1e9, blas / ours, agree);
}

void add_project(CLI::App& bench) {
  auto a = std::make_shared<BenchArgs>();
  auto* project = bench.add_subcommand("project", "Time one projection C = P^T F P of a dense LUT");
  project->add_option("--level,-l", a->level, "Tessellation level")->capture_default_str()->check(CLI::Range(0, 6));
  project->add_option("--order,-n", a->order, "Expansion order")->capture_default_str()->check(CLI::Range(0, 64));
  project->add_option("--threads,-t", a->threads, "Threads (default: all cores)")->check(CLI::Range(0, 1024));
  project->add_option("--repeat", a->repeat, "Timed repetitions (the best is reported)")->capture_default_str()->check(CLI::Range(1, 1000));
  project->add_option("--peak-gflops", a->peak_gflops, "FP64 peak of the machine, when /proc/cpuinfo's clock is not right");
  project->add_flag("--json", a->json, "JSON: seconds, gflops, peak_gflops, peak_ratio, blas_seconds, blas_ratio, ...");
  project->callback([a] { run_project(*a); });
}

const BenchRegistrar kRegistrar("project", add_project);

}  // namespace
}  // namespace icobrdf::cli
