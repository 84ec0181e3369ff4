#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;
using icobrdf::test::TempDir;

namespace ICOBRDF_UNITY_ID {
// Values print in shortest round-trip form; the expected values below are computed here with libm
// trigonometry in a different order than the program: a few ulps.
constexpr double kValueTol = 1e-13;

std::vector<std::vector<double>> parse_csv(const std::string& text, std::string& header) {
  return icobrdf::test::parse_value_csv(text, header);
}

std::string write(const TempDir& d, const std::string& name, const std::string& content) {
  std::ofstream(d.file(name)) << content;
  return d.file(name);
}

double rad(double deg) { return deg * M_PI / 180.0; }

TEST(CliEval, LambertAndMinnaertMatchTheirFormulas) {
  TempDir d;
  const auto pairs = write(d, "p.csv", "theta_i,phi_i,theta_r,phi_r\n0,0,0,0\n30,10,60,200\n89.9,0,45,90\n90,0,90,180\n");
  auto r = run_cli({"eval", "model:lambert:albedo=0.5", "--at", pairs});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string header;
  auto rows = parse_csv(r.out, header);
  EXPECT_EQ(header, "f");
  ASSERT_EQ(rows.size(), 4u);
  for (const auto& row : rows) EXPECT_NEAR(row.at(0), 0.5 / M_PI, kValueTol);
  // Minnaert k = 2: f = 3/(2 pi) cos(theta_i) cos(theta_r).
  r = run_cli({"eval", "model:minnaert:k=2", "--at", pairs});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  rows = parse_csv(r.out, header);
  const double ti[] = {0, 30, 89.9, 90}, tr[] = {0, 60, 45, 90};
  for (int k = 0; k < 4; ++k)
    EXPECT_NEAR(rows.at(k).at(0), 3.0 / (2 * M_PI) * std::cos(rad(ti[k])) * std::cos(rad(tr[k])), kValueTol) << k;
}

TEST(CliEval, RadiansAndPhongPeak) {
  TempDir d;
  // Phong at the mirror direction: f = ks (n+2)/(2 pi); (30 deg, 0) mirrors to (30 deg, 180 deg).
  const auto pairs = write(d, "p.csv", "theta_i,phi_i,theta_r,phi_r\n" + std::to_string(rad(30)) + ",0,"
                                            + std::to_string(rad(30)) + "," + std::to_string(M_PI) + "\n");
  const auto r = run_cli({"eval", "model:phong:n=10,ks=0.5", "--at", pairs, "--radians"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string header;
  const auto rows = parse_csv(r.out, header);
  // The angles went through 6-decimal text: cos(angle to mirror) = 1 - O(1e-12), so f is within 1e-9.
  EXPECT_NEAR(rows.at(0).at(0), 0.5 * 12 / (2 * M_PI), 1e-9);
}

TEST(CliEval, DeltaModelsPrintTheRegularPartWithANote) {
  TempDir d;
  const auto pairs = write(d, "p.csv", "theta_i,phi_i,theta_r,phi_r\n30,0,30,180\n");
  const auto r = run_cli({"eval", "model:mirror+0.05*lambert", "--at", pairs});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string header;
  const auto rows = parse_csv(r.out, header);
  EXPECT_NEAR(rows.at(0).at(0), 0.05 / M_PI, kValueTol);
  EXPECT_NE(r.err.find("mirror delta part of weight 1"), std::string::npos) << r.err;
}

TEST(CliEval, ErrorsExitNonZeroWithoutOutput) {
  TempDir d;
  const auto pairs = write(d, "p.csv", "theta_i,phi_i,theta_r,phi_r\n30,0,30,180\n");
  const auto bad_rows = write(d, "bad.csv", "theta_i,phi_i,theta_r,phi_r\n30,0,30,180\n100,0,0,0\n");
  struct Case {
    std::vector<std::string> args;
    int code;  // -1: any non-zero code (a missing file is the reader's InputError or IoError)
    const char* mention;
  };
  for (const auto& c : std::vector<Case>{
           {{"eval", "model:ggxx", "--at", pairs}, 2, "unknown model 'ggxx'"},
           {{"eval", "model:ggx:alpha=9", "--at", pairs}, 2, "[0.001, 4], got 9"},
           {{"eval", "lambert", "--at", pairs}, 2, "model:NAME"},
           {{"eval", "model:lambert"}, 2, "--at"},
           {{"eval", "model:lambert", "--at", bad_rows}, 3, ":3:"},
           {{"eval", "model:lambert", "--at", d.file("missing.csv")}, -1, "missing.csv"},
       }) {
    const auto r = run_cli(c.args);
    if (c.code > 0) EXPECT_EQ(r.exit_code, c.code) << c.args[1] << ": " << r.err;
    else EXPECT_NE(r.exit_code, 0) << c.args[1];
    EXPECT_TRUE(r.out.empty()) << r.out;
    EXPECT_NE(r.err.find(c.mention), std::string::npos) << r.err;
  }
}

}  // namespace ICOBRDF_UNITY_ID
