#pragma once
// The stand-alone subcommand of a report section (icobrdf/lab/report_section.hpp)
//   icobrdf bench NAME [--levels 1..5] [--orders 0..32] [--quick] [--json] [--report DIR] [--threads T]
// that runs one section (icobrdf/lab/report_section.hpp run_section_alone) and prints its markdown (or its JSON
// data), the same section `bench sweep` includes.
#include <CLI/CLI.hpp>
#include <omp.h>

#include <Eigen/Core>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/option_checks.hpp"
#include "icobrdf/lab/int_list.hpp"
#include "icobrdf/lab/report_section.hpp"

namespace icobrdf::cli::section {

using lab::ReportSectionRunner;
using lab::SectionOptions;

struct SubcommandDefaults {
  std::string levels, orders;              // full run
  std::string quick_levels, quick_orders;  // --quick
  int max_level = 6, max_order = 128;
};

// Adds `bench NAME` running `run` once with the parsed options. Output: "# title" + markdown, or with
// --json {"section", "title", "figures", "data"}; with --report DIR, also DIR/NAME.md and DIR/NAME.json
// (and the figures, which the section writes there). Everything is computed before anything is printed.
inline void add_section_subcommand(CLI::App& bench, const std::string& name, const std::string& description,
                                   const SubcommandDefaults& defaults, ReportSectionRunner run) {
  struct Args {
    std::string levels, orders, report;
    bool quick = false, json = false;
    int threads = 0;
  };
  auto a = std::make_shared<Args>();
  auto* cmd = bench.add_subcommand(name, description);
  cmd->add_option("--levels", a->levels, "Tessellation levels, 'a..b' or a list (default " + defaults.levels + ", quick " + defaults.quick_levels + ")");
  cmd->add_option("--orders", a->orders, "Expansion orders, 'a..b' or a list (default " + defaults.orders + ", quick " + defaults.quick_orders + ")");
  cmd->add_flag("--quick", a->quick, "Small sizes (seconds): smoke runs and tests");
  cmd->add_flag("--json", a->json, "Print the section's data as JSON instead of markdown");
  cmd->add_option("--report", a->report, "Folder for the section's markdown, JSON and PNG figures (created if missing)");
  cmd->add_option("--threads,-t", a->threads, "Threads (default: all cores)")->check(thread_count());
  cmd->callback([a, name, defaults, run] {
    SectionOptions o;
    o.quick = a->quick;
    o.levels = lab::parse_int_list(a->levels.empty() ? (a->quick ? defaults.quick_levels : defaults.levels) : a->levels, 0,
                               defaults.max_level, "--levels");
    o.orders = lab::parse_int_list(a->orders.empty() ? (a->quick ? defaults.quick_orders : defaults.orders) : a->orders, 0,
                               defaults.max_order, "--orders");
    o.threads = a->threads > 0 ? a->threads : omp_get_num_procs();
    omp_set_num_threads(o.threads);
    Eigen::setNbThreads(o.threads);
    o.report_dir = a->report;
    const lab::SectionOutput out = lab::run_section_alone(name, run, o, "bench " + name);
    if (a->json)
      std::cout << out.json.dump(2) << "\n";
    else
      std::cout << out.markdown;
  });
}

}  // namespace icobrdf::cli::section
