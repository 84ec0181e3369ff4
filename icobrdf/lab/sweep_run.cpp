#include "icobrdf/lab/sweep_run.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/lab/staged_folder.hpp"
#include "icobrdf/lab/sweep_report.hpp"

namespace icobrdf::lab::sweep {
namespace {

namespace fs = std::filesystem;

bool writable_dir(const fs::path& p) {
  std::error_code ec;
  return fs::is_directory(p, ec) && ::access(p.c_str(), W_OK | X_OK) == 0;
}

fs::path folder_of(const fs::path& p) { return p.has_parent_path() ? p.parent_path() : fs::path("."); }

}  // namespace

std::pair<std::vector<std::string>, std::vector<std::string>> parse_model_list(const std::string& text, const std::string& models_label) {
  const std::vector<std::string> items = text.empty() ? default_models() : split_model_list(text);
  std::vector<std::string> specs;
  for (const auto& item : items) {
    if (item.empty())
      throw ArgumentError(models_label + " '" + quoted_text(text) + "': empty model in the list, expected SPEC,SPEC,...");
    const auto model = parse_model(item);  // ArgumentError naming the problem
    if (!model->delta_parts().empty())
      throw ArgumentError(models_label + ": '" + item + "' has delta parts, which have no pointwise error; expected models without delta parts");
    const std::string spec = model->spec();
    if (std::find(specs.begin(), specs.end(), spec) != specs.end())
      throw ArgumentError(models_label + ": '" + quoted_text(spec) + "' is listed twice");
    specs.push_back(spec);
  }
  return {specs, items};
}

void check_sweep_outputs(const std::string& output, const std::string& report, const std::string& report_label) {
  std::error_code ec;
  check_output_path(output);
  if (report.empty()) throw ArgumentError(report_label + ": a report folder is required");
  const fs::path dir = fs::path(report).lexically_normal();
  const std::string where = report_label + " " + report;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) throw IoError(where + ": exists and is not a folder");
  if (fs::exists(dir, ec) && !writable_dir(dir)) throw IoError(where + ": folder is not writable");
  if (!writable_dir(folder_of(dir))) throw IoError(where + ": parent folder '" + folder_of(dir).string() + "' is missing or not writable");
}

std::vector<std::string> run_and_write_sweep(SweepResult& r, const std::string& output, const std::string& report,
                                             const std::string& report_label, const std::function<void(const std::string&)>& progress) {
  const fs::path dir = fs::path(report).lexically_normal();
  const fs::path stage = folder_of(dir) / fmt::format(".{}.tmp-{}", dir.filename().string(), ::getpid());
  const std::string label = report_label + " " + dir.string();
  std::error_code ec;
  fs::remove_all(stage, ec);
  if (!fs::create_directory(stage, ec) || ec)
    throw IoError(report_label + " " + report + ": cannot create '" + stage.string() + "': " + ec.message());
  bool wrote_output = false;
  try {
    measure_table(r, progress);
    run_sections(r, stage.string(), progress);
    std::vector<std::string> figures = draw_figures(r, stage.string());
    {
      std::ofstream md(stage / "report.md", std::ios::binary);
      md << report_markdown(r, figures);
      md.close();
      if (!md) throw IoError(report_label + " " + report + ": cannot write report.md");
    }
    check_staged_commit(stage, dir, label);
    write_results_h5(r, output);
    wrote_output = true;
    commit_staged(stage, dir, label);
    return figures;
  } catch (...) {
    fs::remove_all(stage, ec);
    if (wrote_output) fs::remove(output, ec);
    throw;
  }
}

}  // namespace icobrdf::lab::sweep
