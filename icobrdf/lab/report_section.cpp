#include "icobrdf/lab/report_section.hpp"

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/atomic_write.hpp"
#include "icobrdf/lab/baselines.hpp"
#include "icobrdf/lab/hard_cases.hpp"

namespace icobrdf::lab {

const std::map<std::string, ReportSectionRunner>& report_sections() {
  static const std::map<std::string, ReportSectionRunner> sections{{"baselines", run_baselines}, {"hard-cases", run_hard_cases}};
  return sections;
}

SectionOutput run_section_alone(const std::string& name, const ReportSectionRunner& run, const SectionOptions& options,
                                const std::string& label) {
  if (!options.report_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options.report_dir, ec);
    if (ec || !std::filesystem::is_directory(options.report_dir))
      throw IoError(label + ": cannot create report folder '" + options.report_dir.string() + "': " + ec.message());
  }
  const ReportSection s = run(options);
  SectionOutput out{{{"section", name}, {"title", s.title}, {"figures", s.figures}, {"data", s.data}}, "# " + s.title + "\n\n" + s.markdown};
  if (!options.report_dir.empty()) {
    atomic_write_text(options.report_dir / (name + ".md"), out.markdown);
    atomic_write_text(options.report_dir / (name + ".json"), out.json.dump(2) + "\n");
  }
  return out;
}

}  // namespace icobrdf::lab
