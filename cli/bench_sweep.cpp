// icobrdf bench sweep [--levels 1..5] [--orders 0..20] [--models SPEC,SPEC,...] [--threads T] [--held-out N]
//                     [--sampling centre|average] [--gram-tol G] [--quick] [--quiet] [--json] -o RESULTS.h5 --report DIR
// Speed against error: for every (level, order) of the equal-area tessellation, Gram error, condition number,
// the cost of the grid and operators, and per model the cost of one projection and the error of its
// reconstruction at held-out direction pairs (icobrdf/lab/sweep_measure.hpp); then every report section
// (icobrdf/lab/report_section.hpp). Writes RESULTS.h5 (docs/file-format.md, "Sweep results") and DIR/report.md with
// PNG figures (icobrdf/lab/sweep_report.hpp); docs/benchmarks.md explains how to read them.
//
// Lists: levels and orders as "a..b" or "a,b,c"; models as icobrdf/lab/sweep_measure.hpp split_model_list reads
// them. Models with delta parts have no pointwise error: refused.
//
// Nothing is written unless the whole sweep succeeds (icobrdf/lab/sweep_run.hpp).
#include <fmt/core.h>
#include <omp.h>

#include <Eigen/Core>
#include <filesystem>
#include <iostream>
#include <memory>
#include <tuple>

#include "cli/bench_commands.hpp"
#include "cli/option_checks.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/lab/int_list.hpp"
#include "icobrdf/lab/invocation.hpp"
#include "icobrdf/lab/machine.hpp"
#include "icobrdf/lab/sweep_report.hpp"
#include "icobrdf/lab/sweep_run.hpp"

namespace icobrdf::cli {
namespace {

namespace sweep = lab::sweep;

// Defaults: levels 1..5 and orders 0..20 run in a few minutes on 2 cores (docs/benchmarks.md has the
// measured time); level 6 (41088 cells, 16x a level-5 fit) is asked for explicitly.
constexpr const char* kDefaultLevels = "1..5";
constexpr const char* kDefaultOrders = "0..20";
constexpr const char* kQuickLevels = "1..2";
constexpr const char* kQuickOrders = "0..4";
constexpr int kMaxHeldOutPairs = 1000000;

struct SweepArgs {
  std::string levels, orders, models, output, report, sampling = "centre";
  int threads = 0, held_out = 0;
  double gram_tol = 0.1;
  bool quick = false, json = false, quiet = false;
};

void run_sweep(const SweepArgs& a) {
  using namespace lab;
  using namespace sweep;
  SweepResult r;
  SweepConfig& cfg = r.config;
  cfg.quick = a.quick;
  cfg.levels = parse_int_list(a.levels.empty() ? (a.quick ? kQuickLevels : kDefaultLevels) : a.levels, 0, kMaxSweepLevel, "--levels");
  cfg.orders = parse_int_list(a.orders.empty() ? (a.quick ? kQuickOrders : kDefaultOrders) : a.orders, 0, kMaxSweepOrder, "--orders");
  std::tie(cfg.models, cfg.labels) = parse_model_list(a.models, "--models");
  const auto sampling = lut_sampling_named(a.sampling);
  if (!sampling) throw ArgumentError("--sampling: expected 'centre' or 'average', found '" + a.sampling + "'");
  cfg.sampling = *sampling;
  cfg.gram_tolerance = a.gram_tol;
  cfg.held_out = a.held_out > 0 ? a.held_out : (a.quick ? kQuickHeldOutPairs : kDefaultHeldOutPairs);
  cfg.threads = a.threads > 0 ? a.threads : omp_get_num_procs();
  check_sweep_outputs(a.output, a.report, "--report");

  omp_set_num_threads(cfg.threads);
  Eigen::setNbThreads(cfg.threads);
  r.created = lab::now_iso8601();
  r.command_line = lab::command_line();
  r.machine = lab::describe_machine(cfg.threads);
  const auto progress = [&a](const std::string& line) { if (!a.quiet) std::cerr << line << std::endl; };
  const std::vector<std::string> figures = run_and_write_sweep(r, a.output, a.report, "--report", progress);

  const std::string report_md = (std::filesystem::path(a.report).lexically_normal() / "report.md").string();
  std::cout << (a.json ? sweep_summary_json(r, a.output, report_md, figures).dump(2) + "\n" : sweep_summary_text(r, a.output, report_md, figures));
}

void add_sweep(CLI::App& bench) {
  auto a = std::make_shared<SweepArgs>();
  auto* cmd = bench.add_subcommand("sweep", "Speed against error over tessellation levels x expansion orders, with every report section");
  cmd->add_option("--levels", a->levels, fmt::format("Levels, 'a..b' or 'a,b,c' in [0, {}] (default {}, quick {})", sweep::kMaxSweepLevel,
                                                     kDefaultLevels, kQuickLevels));
  cmd->add_option("--orders", a->orders, fmt::format("Orders, 'a..b' or 'a,b,c' in [0, {}] (default {}, quick {})", sweep::kMaxSweepOrder,
                                                     kDefaultOrders, kQuickOrders));
  cmd->add_option("--models", a->models, "Model specs separated by ',' or ';' (default: lambert to ggx alpha 0.05, see `icobrdf models`)");
  cmd->add_option("--threads,-t", a->threads, "Threads (default: all cores)")->check(thread_count());
  cmd->add_option("--held-out", a->held_out, fmt::format("Held-out direction pairs (default {}, quick {})", sweep::kDefaultHeldOutPairs,
                                                         sweep::kQuickHeldOutPairs))
      ->check(CLI::Range(1, kMaxHeldOutPairs));
  cmd->add_option("--sampling", a->sampling, "LUT sampling during fits: centre (as bank build) or average (as fit)")->capture_default_str();
  cmd->add_option("--gram-tol", a->gram_tol, "Largest Gram error max|G - I| a supported (level, order) may have")
      ->capture_default_str()->check(gram_tolerance());
  cmd->add_flag("--quick", a->quick, "Small defaults (levels 1..2, orders 0..4, 200 pairs, quick sections): smoke runs and tests");
  cmd->add_flag("--json", a->json, "Print the results as JSON");
  cmd->add_flag("--quiet,-q", a->quiet, "No progress lines on stderr");
  cmd->add_option("-o,--output", a->output, "RESULTS.h5 (written atomically)")->required();
  cmd->add_option("--report", a->report, "Folder for report.md and the PNG figures (created if missing)")->required();
  cmd->callback([a] { run_sweep(*a); });
}

const BenchRegistrar kBenchSweepRegistrar("sweep", add_sweep);

}  // namespace
}  // namespace icobrdf::cli
