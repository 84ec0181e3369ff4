#pragma once
// Report sections: measurements made apart from the level x order sweep (baselines, hard cases), each run
// by `bench sweep` after its own table and also runnable alone (`bench NAME`). The sweep writes each
// section's markdown into DIR/report.md and its data into RESULTS.h5 under /sections/<name>.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace icobrdf::lab {

// What a report section is given.
struct SectionOptions {
  std::vector<int> levels;               // tessellation levels of the sweep (ascending)
  std::vector<int> orders;               // expansion orders of the sweep (ascending)
  int threads = 1;                       // threads the sweep runs with (already set for OpenMP/Eigen)
  bool quick = false;                    // small sizes and few repetitions (tests, smoke runs)
  std::filesystem::path report_dir;      // existing folder: PNG figures go here; empty: no figures
};

// What a report section gives back.
struct ReportSection {
  std::string title;                     // heading in report.md
  std::string markdown;                  // body: prose and GitHub-markdown tables; figures referenced by file name
  nlohmann::json data;                   // machine-readable figures; stored in RESULTS.h5 under /sections/<name>
  std::vector<std::string> figures;      // PNG file names written into report_dir
};

using ReportSectionRunner = std::function<ReportSection(const SectionOptions&)>;

// Every report section by name ("baselines", "hard-cases"); the sweep runs them in name order.
const std::map<std::string, ReportSectionRunner>& report_sections();

// One section run alone (`bench NAME`): its JSON {"section", "title", "figures", "data"} and its markdown
// "# title" + body. With options.report_dir set, the folder is created if missing (IoError starting with
// `label` when it cannot be) and both are also written there, atomically, as NAME.json and NAME.md, beside
// the figures the section writes. Everything is computed before anything is written.
struct SectionOutput {
  nlohmann::json json;
  std::string markdown;
};
SectionOutput run_section_alone(const std::string& name, const ReportSectionRunner& run, const SectionOptions& options,
                                const std::string& label);

}  // namespace icobrdf::lab
