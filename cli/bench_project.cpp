// icobrdf bench project --level L --order N [--threads T] [--repeat R] [--peak-gflops G] [--json]
// Times one projection C = P^T F P of a cells x cells LUT with the library's call and with raw OpenBLAS in
// the same run (lab/projection_benchmark.hpp), and reports GFLOP/s, the ratio to the machine's FP64 peak
// (lab/machine.hpp, or --peak-gflops) and to the BLAS baseline.
#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <Eigen/Core>
#include <iostream>
#include <memory>

#include "cli/bench_commands.hpp"
#include "cli/option_checks.hpp"
#include "lab/machine.hpp"
#include "lab/projection_benchmark.hpp"

namespace icobrdf::cli {
namespace {

constexpr double kMaxPeakGflops = 1e9;  // an exaflop: beyond any single machine this benchmark runs on

struct BenchArgs {
  int level = 5, order = 8, threads = 0, repeat = 5;
  double peak_gflops = 0.0;
  bool json = false;
};

void run_project(const BenchArgs& a) {
  const int threads = a.threads > 0 ? a.threads : omp_get_num_procs();
  const lab::ProjectionBenchmark b = lab::measure_projection(a.level, a.order, threads, a.repeat);
  const double ours = b.seconds, blas = b.blas_seconds, agree = b.relative_difference_to_blas;
  const double gflops = b.flops / ours / 1e9;
  const double peak = a.peak_gflops > 0 ? a.peak_gflops : lab::fp64_peak_gflops(threads);
  nlohmann::json j{{"level", a.level},      {"order", a.order},          {"cells", b.cells},
                   {"modes", b.modes},      {"threads", threads},        {"seconds", ours},
                   {"gflops", gflops},      {"peak_gflops", peak},       {"peak_ratio", peak > 0 ? gflops / peak : 0.0},
                   {"blas_seconds", blas},  {"blas_ratio", blas / ours}, {"blas_gflops", b.flops / blas / 1e9},
                   {"flops_per_cycle_per_core", lab::flops_per_cycle_per_core()}, {"cpu_mhz", lab::cpu_mhz()},
                   {"relative_difference_to_blas", agree}, {"blas", "OpenBLAS (cblas_dgemm), faster of (F P) and (P^T F) first"},
                   {"blas_seconds_fp_first", b.blas_seconds_fp_first}, {"blas_seconds_pf_first", b.blas_seconds_pf_first},
                   {"eigen_simd", Eigen::SimdInstructionSetsInUse()}};
  if (a.json) {
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << fmt::format("projection C = P^T F P, level {} ({} cells), order {} ({} modes), {} thread(s)\n", a.level, b.cells, a.order,
                           b.modes, threads)
            << fmt::format("  icobrdf (Eigen): {:.4f} s, {:.1f} GFLOP/s = {:.0f}% of the FP64 peak {:.1f} GFLOP/s\n", ours, gflops,
                           100 * gflops / peak, peak)
            << fmt::format("  raw OpenBLAS:    {:.4f} s, {:.1f} GFLOP/s; icobrdf is {:.2f}x its speed (results agree to {:.1e})\n", blas,
                           b.flops / blas / 1e9, blas / ours, agree);
}

void add_project(CLI::App& bench) {
  auto a = std::make_shared<BenchArgs>();
  auto* project = bench.add_subcommand("project", "Time one projection C = P^T F P of a dense LUT");
  project->add_option("--level,-l", a->level, "Tessellation level")->capture_default_str()->check(CLI::Range(0, 6));
  project->add_option("--order,-n", a->order, "Expansion order")->capture_default_str()->check(CLI::Range(0, 64));
  project->add_option("--threads,-t", a->threads, "Threads (default: all cores)")->check(thread_count());
  project->add_option("--repeat", a->repeat, "Timed repetitions (the best is reported)")->capture_default_str()->check(CLI::Range(1, 1000));
  project->add_option("--peak-gflops", a->peak_gflops, "FP64 peak of the machine, when /proc/cpuinfo's clock is not right")
      ->check(finite_in(0.0, kMaxPeakGflops, true));
  project->add_flag("--json", a->json, "JSON: seconds, gflops, peak_gflops, peak_ratio, blas_seconds, blas_ratio, ...");
  project->callback([a] { run_project(*a); });
}

const BenchRegistrar kRegistrar("project", add_project);

}  // namespace
}  // namespace icobrdf::cli
