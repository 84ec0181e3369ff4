#pragma once
// The stand-alone subcommand of a report section (icobrdf/lab/report_section.hpp)
//   icobrdf bench NAME [--levels 1..5] [--orders 0..32] [--quick] [--json] [--report DIR] [--threads T]
// that runs one section and prints its markdown (or its JSON data), the same section `bench sweep` includes,
// and the parsing of level and order lists shared with `bench sweep`.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <nlohmann/json.hpp>
#include <omp.h>

#include <Eigen/Core>
#include <algorithm>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "cli/option_checks.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/atomic_write.hpp"
#include "icobrdf/lab/report_section.hpp"

namespace icobrdf::cli::section {

using lab::ReportSection;
using lab::ReportSectionRunner;
using lab::SectionOptions;

// "a..b" (inclusive) or "a,b,c"; every value in [lo, hi]; ArgumentError otherwise.
inline std::vector<int> parse_int_range(const std::string& text, int lo, int hi, const std::string& what) {
  std::vector<int> v;
  const auto bad = [&] {
    return ArgumentError(fmt::format("{}: expected 'a..b' or a comma list of integers in [{}, {}], got '{}'", what, lo, hi, text));
  };
  try {
    const auto dots = text.find("..");
    if (dots != std::string::npos) {
      size_t p1 = 0, p2 = 0;
      const int a = std::stoi(text.substr(0, dots), &p1), b = std::stoi(text.substr(dots + 2), &p2);
      if (p1 != dots || p2 != text.size() - dots - 2 || a > b) throw bad();
      for (int k = a; k <= b; ++k) v.push_back(k);
    } else {
      size_t start = 0;
      while (start <= text.size()) {
        const auto comma = text.find(',', start);
        const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        size_t p = 0;
        v.push_back(std::stoi(item, &p));
        if (p != item.size()) throw bad();
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
    }
  } catch (const std::logic_error&) {  // stoi's invalid_argument / out_of_range
    throw bad();
  }
  if (v.empty()) throw bad();
  for (int x : v)
    if (x < lo || x > hi) throw bad();
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

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
    o.levels = parse_int_range(a->levels.empty() ? (a->quick ? defaults.quick_levels : defaults.levels) : a->levels, 0,
                               defaults.max_level, "--levels");
    o.orders = parse_int_range(a->orders.empty() ? (a->quick ? defaults.quick_orders : defaults.orders) : a->orders, 0,
                               defaults.max_order, "--orders");
    o.threads = a->threads > 0 ? a->threads : omp_get_num_procs();
    omp_set_num_threads(o.threads);
    Eigen::setNbThreads(o.threads);
    if (!a->report.empty()) {
      std::error_code ec;
      std::filesystem::create_directories(a->report, ec);
      if (ec || !std::filesystem::is_directory(a->report))
        throw IoError("bench " + name + ": cannot create report folder '" + a->report + "': " + ec.message());
      o.report_dir = a->report;
    }
    const ReportSection s = run(o);
    const nlohmann::json j{{"section", name}, {"title", s.title}, {"figures", s.figures}, {"data", s.data}};
    const std::string md = "# " + s.title + "\n\n" + s.markdown;
    if (!o.report_dir.empty()) {
      atomic_write_text(o.report_dir / (name + ".md"), md);
      atomic_write_text(o.report_dir / (name + ".json"), j.dump(2) + "\n");
    }
    if (a->json)
      std::cout << j.dump(2) << "\n";
    else
      std::cout << md;
  });
}

}  // namespace icobrdf::cli::section
