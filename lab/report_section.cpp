#include "lab/report_section.hpp"

#include "lab/baselines.hpp"
#include "lab/hard_cases.hpp"

namespace icobrdf::lab {

const std::map<std::string, ReportSectionRunner>& report_sections() {
  static const std::map<std::string, ReportSectionRunner> sections{{"baselines", run_baselines}, {"hard-cases", run_hard_cases}};
  return sections;
}

}  // namespace icobrdf::lab
