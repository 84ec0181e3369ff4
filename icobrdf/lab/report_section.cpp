#include "icobrdf/lab/report_section.hpp"

#include "icobrdf/lab/baselines.hpp"
#include "icobrdf/lab/hard_cases.hpp"

namespace icobrdf::lab {

const std::map<std::string, ReportSectionRunner>& report_sections() {
  static const std::map<std::string, ReportSectionRunner> sections{{"baselines", run_baselines}, {"hard-cases", run_hard_cases}};
  return sections;
}

}  // namespace icobrdf::lab
