// icobrdf grid: statistics in text and JSON, the geodesic baseline, bad levels, OBJ export (complete file,
// no temporary left behind, no file on failure).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <dirent.h>
#include <fstream>
#include <sstream>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;
using icobrdf::test::TempDir;

namespace ICOBRDF_UNITY_ID {
// Sums of exactly rounded solid angles, printed with 17 digits.
constexpr double kSumTol = 1e-12;
// Whole-cell solid angle 4 pi / (20 4^L) is exact to rounding.
constexpr double kRelTol = 1e-14;

int count_entries(const std::string& dir) {
  int n = 0;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d)) n += std::string(e->d_name) != "." && std::string(e->d_name) != "..";
    closedir(d);
  }
  return n;
}

TEST(CliGrid, JsonStatisticsOfEqualAreaGrid) {
  for (int level : {0, 3}) {
    const auto r = run_cli({"grid", "--level", std::to_string(level), "--json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    // 10 4^L + 2^(L+1) cells, of which 4 * 2^L are halves (derivation in tests/mesh/test_tessellation.cpp).
    const int cells = 10 * (1 << (2 * level)) + (2 << level);
    const double whole = 4 * M_PI / (20.0 * (1 << (2 * level)));
    EXPECT_EQ(j.at("level").get<int>(), level);
    EXPECT_EQ(j.at("cells").get<int>(), cells);
    EXPECT_EQ(j.at("half_cells").get<int>(), 4 << level);
    EXPECT_EQ(j.at("whole_cells").get<int>(), cells - (4 << level));
    EXPECT_NEAR(j.at("solid_angle_max").get<double>(), whole, kRelTol * whole);
    EXPECT_NEAR(j.at("solid_angle_min").get<double>(), whole / 2, kRelTol * whole);
    EXPECT_NEAR(j.at("solid_angle_sum").get<double>(), 2 * M_PI, kSumTol);
    EXPECT_NEAR(j.at("whole_cell_ratio").get<double>(), 1.0, kRelTol);
    EXPECT_GE(j.at("seconds").get<double>(), 0.0);
  }
}

TEST(CliGrid, GeodesicBaselineIsNotEqualArea) {
  const auto r = run_cli({"grid", "--level", "3", "--geodesic", "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("kind").get<std::string>(), "geodesic");
  EXPECT_EQ(j.at("cells").get<int>(), 656);
  EXPECT_NEAR(j.at("solid_angle_sum").get<double>(), 2 * M_PI, kSumTol);
  // Gnomonic cells shrink towards the icosahedron corners: far from equal area.
  EXPECT_GT(j.at("whole_cell_ratio").get<double>(), 1.2);
}

TEST(CliGrid, TextOutputNamesTheFigures) {
  const auto r = run_cli({"grid", "--level", "1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("44 cells"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max/min"), std::string::npos);
}

TEST(CliGrid, BadLevelIsAUsageError) {
  for (const char* level : {"9", "-1", "abc"}) {
    const auto r = run_cli({"grid", "--level", level});
    EXPECT_EQ(r.exit_code, 2) << level;
    EXPECT_TRUE(r.out.empty()) << level;
    EXPECT_FALSE(r.err.empty());
  }
  EXPECT_EQ(run_cli({"grid"}).exit_code, 2);  // --level is required
}

TEST(CliGrid, ExportsACompleteObj) {
  TempDir dir;
  const std::string path = dir.file("grid.obj");
  const auto r = run_cli({"grid", "--level", "2", "--export-obj", path});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::ifstream in(path);
  ASSERT_TRUE(in.good());
  std::string line;
  int v = 0, f = 0;
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      double x, y, z;
      ls >> x >> y >> z;
      EXPECT_NEAR(x * x + y * y + z * z, 1.0, 1e-14);
      EXPECT_GE(z, -1e-15);
      ++v;
    } else if (tag == "f") {
      ++f;
    }
  }
  EXPECT_EQ(f, 168);  // 10 * 16 + 8 cells at level 2
  // A disk of triangles (Euler characteristic V - E + F = 1) with B = 6 * 2^L = 24 boundary edges:
  // 3 F = 2 E - B gives E = (3 * 168 + 24) / 2 = 264, so V = 1 + 264 - 168 = 97.
  EXPECT_EQ(v, 97);
  EXPECT_EQ(count_entries(dir.path), 1);  // no temporary left behind
}

TEST(CliGrid, FailedExportLeavesNoFile) {
  TempDir dir;
  const std::string path = dir.file("missing-dir/grid.obj");
  const auto r = run_cli({"grid", "--level", "1", "--export-obj", path});
  EXPECT_EQ(r.exit_code, 5);  // IoError
  EXPECT_NE(r.err.find("grid.obj"), std::string::npos);
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1);  // one line
  EXPECT_EQ(count_entries(dir.path), 0);
  // Target is a directory: rename fails, the temporary is removed.
  const auto r2 = run_cli({"grid", "--level", "1", "--export-obj", dir.path});
  EXPECT_EQ(r2.exit_code, 5);
  EXPECT_EQ(count_entries(dir.path), 0);
}

}  // namespace ICOBRDF_UNITY_ID
