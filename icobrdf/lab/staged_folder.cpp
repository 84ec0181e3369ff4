#include "icobrdf/lab/staged_folder.hpp"

#include <algorithm>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/output_path.hpp"

namespace icobrdf::lab {

namespace fs = std::filesystem;

void check_staged_commit(const fs::path& stage, const fs::path& dir, const std::string& label) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return;
  for (const auto& e : fs::directory_iterator(stage)) {
    try {
      check_output_target(dir / e.path().filename());  // the rename below would replace a FIFO, device or link
    } catch (const IoError& err) {
      throw IoError(label + ": " + err.what());
    }
  }
}

void commit_staged(const fs::path& stage, const fs::path& dir, const std::string& label) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) {
    fs::rename(stage, dir, ec);
    if (ec) throw IoError(label + ": cannot move the report into place: " + ec.message());
    return;
  }
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(stage)) files.push_back(e.path());
  std::stable_partition(files.begin(), files.end(), [](const fs::path& p) { return p.filename() != "report.md"; });
  for (const auto& f : files) {
    fs::rename(f, dir / f.filename(), ec);
    if (ec) throw IoError(label + ": cannot move '" + f.filename().string() + "' into place: " + ec.message());
  }
  fs::remove_all(stage, ec);
}

}  // namespace icobrdf::lab
