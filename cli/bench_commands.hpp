#pragma once
// Registries of the `icobrdf bench` family, so each benchmark lives in its own cli/bench_<name>.cpp:
// - BenchRegistrar: a subcommand of `bench` (project, sweep, ...), added in name order by cli/cmd_bench.cpp;
//     static const icobrdf::cli::BenchRegistrar reg("name", [](CLI::App& bench) { bench.add_subcommand(...); });
// - ReportSectionRegistrar: a section of the `bench sweep` report measured apart from the level x order
//   sweep (baselines, hard cases, ...). The sweep runs every registered section, in name order, after its
//   own table, writes each section's markdown into DIR/report.md and its data into RESULTS.h5.
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace icobrdf::cli {

using BenchAdder = std::function<void(CLI::App& bench)>;

inline std::map<std::string, BenchAdder>& bench_registry() {
  static std::map<std::string, BenchAdder> registry;
  return registry;
}

struct BenchRegistrar {
  BenchRegistrar(const std::string& name, BenchAdder adder) { bench_registry()[name] = std::move(adder); }
};

// What a report section is given.
struct SectionOptions {
  std::vector<int> levels;               // tessellation levels of the sweep (ascending)
  std::vector<int> orders;               // expansion orders of the sweep (ascending)
  int threads = 1;                       // threads the sweep runs with (already set for OpenMP/Eigen)
  bool quick = false;                    // small sizes and few repetitions (tests, smoke runs)
  std::filesystem::path report_dir;      // existing folder: PNG figures go here
};

// What a report section gives back.
struct ReportSection {
  std::string title;                     // heading in report.md
  std::string markdown;                  // body: prose and GitHub-markdown tables; figures referenced by file name
  nlohmann::json data;                   // machine-readable figures; stored in RESULTS.h5 under /sections/<name>
  std::vector<std::string> figures;      // PNG file names written into report_dir
};

using ReportSectionRunner = std::function<ReportSection(const SectionOptions&)>;

inline std::map<std::string, ReportSectionRunner>& report_section_registry() {
  static std::map<std::string, ReportSectionRunner> registry;
  return registry;
}

struct ReportSectionRegistrar {
  ReportSectionRegistrar(const std::string& name, ReportSectionRunner run) {
    report_section_registry()[name] = std::move(run);
  }
};

}  // namespace icobrdf::cli
