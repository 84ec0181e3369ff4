// Pieces of the measurement lab that the CLI tests reach only through whole runs: the model list of
// `bench sweep`, the Pareto front of a sweep, the staged report commit and the report number formats.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/lab/report_format.hpp"
#include "icobrdf/lab/staged_folder.hpp"
#include "icobrdf/lab/sweep_measure.hpp"
#include "icobrdf/lab/sweep_report.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

namespace fs = std::filesystem;
using namespace icobrdf;
using namespace icobrdf::lab;

TEST(LabModelList, KeyValueItemsContinueThePreviousModel) {
  using V = std::vector<std::string>;
  EXPECT_EQ(sweep::split_model_list("lambert,ggx:alpha=0.2,f0=0.04"), (V{"lambert", "ggx:alpha=0.2,f0=0.04"}));
  EXPECT_EQ(sweep::split_model_list(" lambert ; phong:n=20 "), (V{"lambert", "phong:n=20"}));
  EXPECT_EQ(sweep::split_model_list("0.8*lambert+0.2*ggx:alpha=0.1,minnaert:k=1.5"), (V{"0.8*lambert+0.2*ggx:alpha=0.1", "minnaert:k=1.5"}));
  EXPECT_EQ(sweep::split_model_list("lambert,,ggx"), (V{"lambert", "", "ggx"}));  // the caller refuses the empty item
}

sweep::SweepRow row(double seconds, double error, bool supported = true) {
  sweep::SweepRow r;
  r.supported = supported;
  r.models = {sweep::ModelCell{seconds, error, error, error}};
  return r;
}

TEST(LabParetoFront, KeepsExactlyTheUndominatedSupportedRowsFastestFirst) {
  sweep::SweepResult r;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.rows = {row(3.0, 1e-3), row(1.0, 1e-1), row(2.0, 1e-1), row(0.5, 1e-4, false), row(2.0, 1e-2), row(4.0, 1e-3), row(nan, nan)};
  EXPECT_EQ(sweep::pareto_front(r, 0), (std::vector<std::size_t>{1, 4, 0}));
}

struct TempDir {
  fs::path path = fs::temp_directory_path() / ("icobrdf_lab_test_" + std::to_string(::getpid()));
  TempDir() { fs::create_directories(path); }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

void touch(const fs::path& p, const std::string& text) { std::ofstream(p) << text; }

// A staging folder and an existing report folder, side by side in a fresh temporary folder.
struct StagedFolders {
  TempDir t;
  fs::path stage = t.path / "stage", dir = t.path / "report";
  StagedFolders() {
    fs::create_directories(stage);
    fs::create_directories(dir);
  }
};

TEST(LabStagedFolder, CommitMovesStagedFilesAndKeepsOthers) {
  const StagedFolders f;
  const fs::path &stage = f.stage, &dir = f.dir;
  touch(stage / "report.md", "new");
  touch(stage / "a.png", "png");
  touch(dir / "report.md", "old");
  touch(dir / "notes.txt", "mine");
  check_staged_commit(stage, dir, "report");
  commit_staged(stage, dir, "report");
  EXPECT_FALSE(fs::exists(stage));
  std::ifstream in(dir / "report.md");
  std::string text;
  in >> text;
  EXPECT_EQ(text, "new");
  EXPECT_TRUE(fs::exists(dir / "a.png"));
  EXPECT_TRUE(fs::exists(dir / "notes.txt"));
}

// A folder, a FIFO or a symbolic link where a staged file goes: the rename would replace it (a FIFO or link
// silently), so it is refused before anything moves, and left as it was.
TEST(LabStagedFolder, AnythingButAFileInTheWayIsRefusedBeforeAnythingMoves) {
  struct Case {
    std::string made, fragment;
  } cases[] = {{"folder", "is a folder"}, {"fifo", "is a FIFO"}, {"link", "is a symbolic link"}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.made);
    const StagedFolders f;
    const fs::path &stage = f.stage, &dir = f.dir;
    touch(stage / "a.png", "png");
    touch(dir / "mine.png", "mine");
    if (c.made == "folder") fs::create_directories(dir / "a.png");
    if (c.made == "fifo") {
      ASSERT_EQ(::mkfifo((dir / "a.png").c_str(), 0644), 0);
    }
    if (c.made == "link") fs::create_symlink("mine.png", dir / "a.png");
    const auto type = fs::symlink_status(dir / "a.png").type();
    try {
      check_staged_commit(stage, dir, "LABEL");
      ADD_FAILURE() << "expected IoError";
    } catch (const IoError& e) {
      const std::string m = e.what();
      EXPECT_EQ(m.rfind("LABEL: " + (dir / "a.png").string(), 0), 0u) << m;
      EXPECT_NE(m.find(c.fragment), std::string::npos) << m;
    }
    EXPECT_TRUE(fs::exists(stage / "a.png"));
    EXPECT_EQ(fs::symlink_status(dir / "a.png").type(), type);
  }
}

TEST(LabReportFormat, NumbersAndTables) {
  EXPECT_EQ(sci(0.0), "0");
  EXPECT_EQ(sci(std::nan("")), "nan");
  EXPECT_EQ(sci(-std::numeric_limits<double>::infinity()), "-inf");
  EXPECT_EQ(sci(1.234e-4), "1.23e-04");
  EXPECT_EQ(fixed(2.0, 1), "2.0");
  EXPECT_EQ(md_table({"a", "b"}, {{"1", "2"}}), "| a | b |\n|---|---|\n| 1 | 2 |\n\n");
  EXPECT_TRUE(num(std::numeric_limits<double>::infinity()).is_null());
  EXPECT_EQ(num(0.5).get<double>(), 0.5);
}

TEST(LabSweepSummary, TextNamesPairsLevelsAndFiles) {
  sweep::SweepResult r;
  r.rows.resize(6);
  r.config.models = {"lambert", "ggx:alpha=0.3"};
  r.table_seconds = 12.3;
  r.sections_seconds = 3.5;
  r.support = {{1, 42, 7}, {2, 168, sweep::kSupportSearchOrder}};
  const std::vector<std::string> figures{"a.png", "b.png", "c.png"};
  EXPECT_EQ(sweep::sweep_summary_text(r, "r.h5", "rep/report.md", figures),
            "bench sweep: 6 (level, order) pairs x 2 models in 12.3 s, report sections in 3.5 s\n"
            "  level 1 (42 cells): supports order 7\n"
            "  level 2 (168 cells): supports order >= " + std::to_string(sweep::kSupportSearchOrder) + "\n"
            "wrote r.h5 and rep/report.md (3 sweep figures, 0 sections)\n");
}

}  // namespace
