// icobrdf bench project --level L --order N [--threads T] [--repeat R] [--peak-gflops G] [--symmetric] [--simd-target T]
//                       [--no-best-blas] [--json]
// Times one projection C = P^T F P of a cells x cells LUT with the library's call and with raw OpenBLAS in
// the same run (icobrdf/lab/projection_benchmark.hpp), and reports GFLOP/s, the ratio to the machine's measured FP64
// peak (icobrdf/lab/machine.hpp; --peak-gflops overrides it) next to the nominal one, the memory floor of streaming F
// once at the measured bandwidth, and the ratio to the BLAS baseline twice: OpenBLAS as this process loaded
// it, and OpenBLAS on the kernel it picks for the CPU, timed in a child process (this program again, with
// the hidden --blas-only) whose environment lacks OPENBLAS_CORETYPE and OPENBLAS_L2_SIZE, and, when that
// kernel is narrower than the CPU's widest vectors (a CPU newer than the OpenBLAS build), again with
// OPENBLAS_CORETYPE naming the widest kernel: the faster is the baseline. The parent's environment is not
// changed. A child that fails is reported, not fatal (old OpenBLAS builds can crash without those variables
// on some CPUs).
#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <Eigen/Core>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/bench_commands.hpp"
#include "cli/option_checks.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/simd_target.hpp"
#include "icobrdf/blas/blas_dense_kernels.hpp"
#include "icobrdf/lab/child_process.hpp"
#include "icobrdf/lab/machine.hpp"
#include "icobrdf/lab/projection_benchmark.hpp"

namespace icobrdf::cli {
namespace {

constexpr double kMaxPeakGflops = 1e9;  // an exaflop: beyond any single machine this benchmark runs on
// The variables OpenBLAS reads at load time to override its own choice of kernel and cache size.
const std::vector<std::string> kBlasOverrides = {"OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE"};

struct BenchArgs {
  int level = 5, order = 8, threads = 0, repeat = 5;
  double peak_gflops = 0.0;
  bool json = false, no_best_blas = false, blas_only = false, symmetric = false;
  std::string simd_target;  // empty: the best this CPU runs
};

nlohmann::json matrix_json(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    std::vector<double> row(static_cast<size_t>(m.cols()));
    for (Eigen::Index j = 0; j < m.cols(); ++j) row[static_cast<size_t>(j)] = m(i, j);
    rows.push_back(row);
  }
  return rows;
}

Eigen::MatrixXd matrix_of(const nlohmann::json& rows, Eigen::Index n) {
  Eigen::MatrixXd m(n, n);
  if (!rows.is_array() || static_cast<Eigen::Index>(rows.size()) != n) throw std::runtime_error("coefficients are not " + std::to_string(n) + " rows");
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& row = rows[static_cast<size_t>(i)];
    if (!row.is_array() || static_cast<Eigen::Index>(row.size()) != n) throw std::runtime_error("a coefficient row is not " + std::to_string(n) + " long");
    for (Eigen::Index j = 0; j < n; ++j) m(i, j) = row[static_cast<size_t>(j)].get<double>();
  }
  return m;
}

// The child's side: OpenBLAS alone, as JSON.
void run_blas_only(const BenchArgs& a, int threads) {
  const lab::BlasProjection b = lab::measure_blas_projection(a.level, a.order, threads, a.repeat, a.symmetric);
  const nlohmann::json j{{"blas_seconds", b.seconds},         {"blas_cpu_seconds", b.cpu_seconds},         {"blas_seconds_fp_first", b.seconds_fp_first},
                         {"blas_seconds_pf_first", b.seconds_pf_first}, {"blas_core", b.core},
                         {"blas_config", b.config},           {"coefficients", matrix_json(b.coefficients)}};
  std::cout << j.dump() << "\n";
}

// One child run: this program again, --blas-only, without the OpenBLAS overrides and with `added` set.
// Returns the JSON the report carries: seconds, core, agreement with our C; or {"error": ...}.
nlohmann::json blas_child(const BenchArgs& a, int threads, const lab::ProjectionBenchmark& ours, const std::vector<std::string>& added,
                          const std::string& environment) {
  std::vector<std::string> args = {lab::own_executable(), "bench", "project", "--blas-only", "--level", std::to_string(a.level),
                                   "--order", std::to_string(a.order), "--threads", std::to_string(threads), "--repeat",
                                   std::to_string(a.repeat)};
  if (a.symmetric) args.push_back("--symmetric");
  const lab::ChildResult r = lab::run_child(args, kBlasOverrides, added);
  if (r.signal != 0) return {{"error", fmt::format("the OpenBLAS run {} was killed by signal {}", environment, r.signal)}};
  if (r.exit_code != 0)
    return {{"error", fmt::format("the OpenBLAS run {} exited with {}: {}", environment, r.exit_code, r.err.substr(0, r.err.find('\n')))}};
  try {
    const auto c = nlohmann::json::parse(r.out);
    const Eigen::MatrixXd coefficients = matrix_of(c.at("coefficients"), ours.modes);
    const double seconds = c.at("blas_seconds").get<double>();
    return {{"seconds", seconds},
            {"seconds_fp_first", c.at("blas_seconds_fp_first")},
            {"seconds_pf_first", c.at("blas_seconds_pf_first")},
            {"gflops", ours.flops / seconds / 1e9},
            {"ratio", seconds / ours.seconds},
            {"cpu_seconds", c.at("blas_cpu_seconds")},
            {"cpu_ratio", c.at("blas_cpu_seconds").get<double>() / ours.cpu_seconds},
            {"core", c.at("blas_core")},
            {"config", c.at("blas_config")},
            {"relative_difference", lab::relative_difference(ours.coefficients, coefficients)},
            {"environment", environment}};
  } catch (const std::exception& e) {
    return {{"error", fmt::format("the OpenBLAS run {} printed no readable result: {}", environment, e.what())}};
  }
}

// OpenBLAS at its best: a child on the kernel OpenBLAS picks itself (without OPENBLAS_CORETYPE and
// OPENBLAS_L2_SIZE); when that kernel is narrower than the CPU's widest vectors, a second child with
// OPENBLAS_CORETYPE naming the widest kernel. The faster successful run is the baseline; the other is kept
// under "other" so that both are reported.
nlohmann::json best_blas(const BenchArgs& a, int threads, const lab::ProjectionBenchmark& ours) {
  nlohmann::json own = blas_child(a, threads, ours, {}, "without OPENBLAS_CORETYPE and OPENBLAS_L2_SIZE");
  const BlasKernel widest = widest_blas_kernel_for_cpu();
  if (own.contains("error") || widest.core.empty() || blas_kernel_vector_bits(own.at("core").get<std::string>()) >= widest.vector_bits)
    return own;
  nlohmann::json forced =
      blas_child(a, threads, ours, {"OPENBLAS_CORETYPE=" + widest.core}, "with OPENBLAS_CORETYPE=" + widest.core);
  if (forced.contains("error") || forced.at("seconds").get<double>() >= own.at("seconds").get<double>()) {
    own["other"] = forced;
    return own;
  }
  forced["other"] = own;
  return forced;
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
  if (a.blas_only) return run_blas_only(a, threads);
  std::unique_ptr<ScopedSimdTarget> forced;  // UnsupportedError when the CPU cannot run it
  if (!a.simd_target.empty()) forced = std::make_unique<ScopedSimdTarget>(target_named(a.simd_target));
  const std::string load_before = lab::load_average();
  const lab::ProjectionBenchmark b = lab::measure_projection(a.level, a.order, threads, a.repeat, a.symmetric);
  const double measured_peak = a.peak_gflops > 0 ? 0.0 : lab::measure_fp64_peak_gflops(threads);
  const double bandwidth = lab::measure_bandwidth_gbs(threads);
  const nlohmann::json best = a.no_best_blas ? nlohmann::json(nullptr) : best_blas(a, threads, b);
  const double ours = b.seconds, blas = b.blas.seconds, agree = b.relative_difference_to_blas;
  const double gflops = b.flops / ours / 1e9;                    // general-product flops per second (comparable with BLAS)
  const double performed_gflops = b.performed_flops / ours / 1e9;  // what the peak ratio uses
  const double nominal = lab::fp64_peak_gflops(threads);
  const double peak = a.peak_gflops > 0 ? a.peak_gflops : measured_peak;
  const double lut_bytes = 8.0 * static_cast<double>(b.cells) * static_cast<double>(b.cells);
  const double stream_seconds = lut_bytes / (bandwidth * 1e9);  // F read once: the memory floor of the projection
  nlohmann::json j{{"level", a.level},      {"order", a.order},          {"cells", b.cells},  {"symmetric", a.symmetric},
                   {"modes", b.modes},      {"threads", threads},        {"seconds", ours},
                   {"gflops", gflops},      {"peak_gflops", peak},       {"peak_ratio", peak > 0 ? performed_gflops / peak : 0.0},
                   {"performed_gflops", performed_gflops},
                   {"peak_source", a.peak_gflops > 0 ? "--peak-gflops" : "measured"},
                   {"measured_peak_gflops", measured_peak}, {"nominal_peak_gflops", nominal},
                   {"fma_chains_per_thread", lab::kFmaChains}, {"simd_target", lab::simd_target_description()},
                   {"bandwidth_gbs", bandwidth}, {"stream_seconds", stream_seconds}, {"stream_ratio", stream_seconds / ours},
                   {"lut_huge_page_fraction", b.lut_huge_page_fraction},
                   {"blas_seconds", blas},  {"blas_ratio", blas / ours}, {"blas_gflops", b.flops / blas / 1e9},
                   {"cpu_seconds", b.cpu_seconds}, {"blas_cpu_seconds", b.blas.cpu_seconds}, {"blas_cpu_ratio", b.blas.cpu_seconds / b.cpu_seconds},
                   {"blas_core", b.blas.core}, {"blas_config", b.blas.config},
                   {"flops_per_cycle_per_core", lab::flops_per_cycle_per_core()}, {"cpu_mhz", lab::cpu_mhz()},
                   {"relative_difference_to_blas", agree}, {"blas", "OpenBLAS (cblas_dgemm), faster of (F P) and (P^T F) first"},
                   {"blas_seconds_fp_first", b.blas.seconds_fp_first}, {"blas_seconds_pf_first", b.blas.seconds_pf_first},
                   {"blas_best", best},
                   {"eigen_simd", Eigen::SimdInstructionSetsInUse()}, {"cpu_model", lab::cpu_model()},
                   {"load_before", load_before}, {"load_after", lab::load_average()}};
  if (a.json) {
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << fmt::format("projection C = P^T F P, level {} ({} cells), order {} ({} modes), {} thread(s){}\n", a.level, b.cells, a.order,
                           b.modes, threads, a.symmetric ? ", symmetric F (icobrdf reads half of it; OpenBLAS does the general product)" : "")
            << fmt::format("  machine: {}; kernels on {}; load {} before, {} after\n", lab::cpu_model(), lab::simd_target_description(),
                           load_before, lab::load_average())
            << fmt::format("  FP64 peak: {:.1f} GFLOP/s {}; nominal {:.1f} ({:.0f} MHz x {} flops/cycle x cores)\n", peak,
                           a.peak_gflops > 0 ? "(--peak-gflops)" : "measured (FMA throughput on all threads)", nominal, lab::cpu_mhz(),
                           lab::flops_per_cycle_per_core())
            << fmt::format("  memory: {:.1f} GB/s (triad); reading F once ({:.0f} MB) takes {:.4f} s; {:.0f}% of F in huge pages\n",
                           bandwidth, lut_bytes / 1e6, stream_seconds, 100 * b.lut_huge_page_fraction)
            << fmt::format("  icobrdf:                {:.4f} s ({:.4f} s CPU), {:.1f} GFLOP/s = {:.0f}% of the FP64 peak\n", ours, b.cpu_seconds,
                           gflops, 100 * performed_gflops / peak)
            << fmt::format("  OpenBLAS ({}): {:.4f} s ({:.4f} s CPU), {:.1f} GFLOP/s; icobrdf is {:.2f}x its speed ({:.2f}x in CPU time; results "
                           "agree to {:.1e})\n",
                           b.blas.core, blas, b.blas.cpu_seconds, b.flops / blas / 1e9, blas / ours, b.blas.cpu_seconds / b.cpu_seconds, agree);
  if (best.is_null()) return;
  if (best.contains("error")) {
    std::cout << "  OpenBLAS at its best: not measured (" << best["error"].get<std::string>() << ")\n";
    return;
  }
  const auto line = [](const char* what, const nlohmann::json& r) {
    if (r.contains("error")) return fmt::format("  {}: not measured ({})\n", what, r["error"].get<std::string>());
    return fmt::format("  {} ({}, child {}): {:.4f} s ({:.4f} s CPU), {:.1f} GFLOP/s; icobrdf is {:.2f}x its speed ({:.2f}x in CPU time; "
                       "results agree to {:.1e})\n",
                       what, r["core"].get<std::string>(), r["environment"].get<std::string>(), r["seconds"].get<double>(),
                       r["cpu_seconds"].get<double>(), r["gflops"].get<double>(), r["ratio"].get<double>(), r["cpu_ratio"].get<double>(),
                       r["relative_difference"].get<double>());
  };
  std::cout << line("OpenBLAS at its best", best);
  if (best.contains("other")) std::cout << line("OpenBLAS, the other kernel", best["other"]);
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
