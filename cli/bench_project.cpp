// icobrdf bench project --level L --order N [--threads T] [--repeat R] [--peak-gflops G] [--symmetric] [--simd-target T]
//                       [--no-best-blas] [--json]
// Times one projection C = P^T F P of a cells x cells LUT with the library's call and with raw OpenBLAS in
// the same run and reports GFLOP/s against the machine's FP64 peak (--peak-gflops overrides the measured one),
// the memory floor and the OpenBLAS baselines (icobrdf/lab/projection_report.hpp). The child process that
// times OpenBLAS on its own kernel is this program again, with the hidden --blas-only.
#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/bench_commands.hpp"
#include "cli/option_checks.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/simd_target.hpp"
#include "icobrdf/lab/child_process.hpp"
#include "icobrdf/lab/projection_report.hpp"

namespace icobrdf::cli {
namespace {

constexpr double kMaxPeakGflops = 1e9;  // an exaflop: beyond any single machine this benchmark runs on

struct BenchArgs {
  int level = 5, order = 8, threads = 0, repeat = 5;
  double peak_gflops = 0.0;
  bool json = false, no_best_blas = false, blas_only = false, symmetric = false;
  std::string simd_target;  // empty: the best this CPU runs
};

// This program again, timing OpenBLAS alone at the same sizes (the child of lab::projection_report).
std::vector<std::string> blas_child_command(const BenchArgs& a, int threads) {
  std::vector<std::string> args = {lab::own_executable(), "bench", "project", "--blas-only", "--level", std::to_string(a.level),
                                   "--order", std::to_string(a.order), "--threads", std::to_string(threads), "--repeat",
                                   std::to_string(a.repeat)};
  if (a.symmetric) args.push_back("--symmetric");
  return args;
}

// The compiled target named `name` (icobrdf/core/support/simd_target.hpp); ArgumentError listing the compiled ones otherwise.
SimdTarget target_named(const std::string& name) {
  std::string names;
  for (const auto& t : compiled_simd_targets()) {
    if (t.name == name) return t;
    names += (names.empty() ? "" : ", ") + t.name;
  }
  throw ArgumentError("--simd-target '" + name + "': not compiled into this build, expected one of " + names);
}

void run_project(const BenchArgs& a) {
  const int threads = a.threads > 0 ? a.threads : omp_get_num_procs();
  if (a.blas_only) {
    std::cout << lab::blas_only_report(a.level, a.order, threads, a.repeat, a.symmetric).dump() << "\n";
    return;
  }
  std::unique_ptr<ScopedSimdTarget> forced;  // UnsupportedError when the CPU cannot run it
  if (!a.simd_target.empty()) forced = std::make_unique<ScopedSimdTarget>(target_named(a.simd_target));
  lab::ProjectionRequest q;
  q.level = a.level;
  q.order = a.order;
  q.threads = threads;
  q.repeat = a.repeat;
  q.symmetric = a.symmetric;
  q.peak_gflops = a.peak_gflops;
  q.peak_given_by = "--peak-gflops";
  if (!a.no_best_blas) q.blas_child = blas_child_command(a, threads);
  const nlohmann::json j = lab::projection_report(q);
  if (a.json)
    std::cout << j.dump(2) << "\n";
  else
    std::cout << lab::projection_report_text(j);
}

void add_project(CLI::App& bench) {
  auto a = std::make_shared<BenchArgs>();
  auto* project = bench.add_subcommand("project", "Time one projection C = P^T F P of a dense LUT");
  project->add_option("--level,-l", a->level, "Tessellation level")->capture_default_str()->check(CLI::Range(0, 6));
  project->add_option("--order,-n", a->order, "Expansion order")->capture_default_str()->check(CLI::Range(0, 64));
  project->add_option("--threads,-t", a->threads, "Threads (default: all cores)")->check(thread_count());
  project->add_option("--repeat", a->repeat, "Timed repetitions (the best is reported)")->capture_default_str()->check(CLI::Range(1, 1000));
  project->add_option("--peak-gflops", a->peak_gflops, "FP64 peak of the machine for the ratio (default: measured)")
      ->check(finite_in(0.0, kMaxPeakGflops, true));
  project->add_flag("--no-best-blas", a->no_best_blas,
                    "Skip the OpenBLAS run on its own kernel (a child process without OPENBLAS_CORETYPE / OPENBLAS_L2_SIZE)");
  project->add_flag("--symmetric", a->symmetric,
                    "Symmetric F (a reciprocal BRDF's LUT): the library uses it, OpenBLAS does the general product; gflops count the general flops, the peak ratio the performed ones");
  project->add_option("--simd-target", a->simd_target,
                      "Run the dispatched kernels and the peak loop on this compiled SIMD target (AVX3, AVX2, ...; default: the best "
                      "this CPU runs)");
  project->add_flag("--blas-only", a->blas_only, "Time OpenBLAS alone and print JSON (the child run)")->group("");
  project->add_flag("--json", a->json, "JSON: seconds, gflops, peak_gflops, peak_ratio, blas_seconds, blas_ratio, blas_best, ...");
  project->callback([a] { run_project(*a); });
}

const BenchRegistrar kBenchProjectRegistrar("project", add_project);

}  // namespace
}  // namespace icobrdf::cli
