// Issue #19, class 3 through the program: overflow refused by every evaluating command (eval, fit, plot)
// with exit 4 and nothing on stdout or on disk; negative reflectance reported as non-physical (warning,
// exit 3 under --strict) by fit, eval, lut and albedo. The hostile inputs are SCATMECH coefficient files and
// CSV samples written here, and model weights near the double range.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::run_cli;
using icobrdf::test::TempDir;

constexpr int kExitInput = 3, kExitUnsupported = 4;

bool exists(const std::string& p) {
  struct stat st{};
  return ::stat(p.c_str(), &st) == 0;
}

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

std::string pairs(const TempDir& d) {
  std::ofstream(d.file("p.csv")) << "theta_i,phi_i,theta_r,phi_r\n0,0,0,0\n30,10,60,200\n";
  return d.file("p.csv");
}

TEST(CliFiniteValues, OverflowIsRefusedByEveryEvaluatingCommand) {
  TempDir d;
  // Two GGX lobes of weight 1e308 (each weight finite): their sum leaves the double range at the mirror pair.
  const std::string huge = "model:1e308*ggx:alpha=0.05+1e308*ggx:alpha=0.05";
  // Control: the same at 1e300 evaluates to finite values, so the refusal below is the overflow.
  auto r = run_cli({"eval", "model:1e300*ggx:alpha=0.05+1e300*ggx:alpha=0.05", "--at", pairs(d)});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("inf"), std::string::npos) << r.out;
  r = run_cli({"eval", huge, "--at", pairs(d)});
  EXPECT_EQ(r.exit_code, kExitUnsupported) << r.out << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("expected finite values"), std::string::npos) << r.err;
  for (const std::vector<std::string>& cmd :
       {std::vector<std::string>{"fit", huge, "--order", "2", "--level", "2", "-o", d.file("x.h5")},
        std::vector<std::string>{"plot", "slice", huge, "--order", "2", "--level", "2", "-o", d.file("x.png")},
        std::vector<std::string>{"lut", huge, "--order", "2", "--level", "1", "-o", d.file("x.h5")}}) {
    r = run_cli(cmd);
    EXPECT_EQ(r.exit_code, kExitUnsupported) << cmd[0] << ": " << r.out << r.err;
    EXPECT_EQ(lines(r.err), 1) << r.err;
    EXPECT_FALSE(exists(d.file("x.h5")) || exists(d.file("x.png"))) << cmd[0];
  }
}

// f = a I_00^0 = a / (2 pi) (SCATMECH's basis): directional albedo = pi f = a / 2, so a = -1 gives -0.5.
TEST(CliFiniteValues, NegativeReflectanceIsNonPhysical) {
  TempDir d;
  std::ofstream(d.file("neg.txt")) << "1,1,0,0,0,0,0,-1\n";
  const std::string neg = "scatmech:" + d.file("neg.txt");
  auto r = run_cli({"eval", neg, "--at", pairs(d)});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find(std::to_string(-1 / (2 * M_PI)).substr(0, 8)), std::string::npos) << r.out;
  EXPECT_EQ(lines(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("icobrdf: warning:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("non-physical"), std::string::npos) << r.err;
  r = run_cli({"eval", neg, "--at", pairs(d), "--strict"});
  EXPECT_EQ(r.exit_code, kExitInput) << r.err;
  EXPECT_EQ(r.out, "");

  r = run_cli({"fit", neg, "--order", "2", "--level", "2", "-o", d.file("s.h5"), "--strict"});
  EXPECT_EQ(r.exit_code, kExitInput) << r.err;
  EXPECT_FALSE(exists(d.file("s.h5")));
  r = run_cli({"fit", neg, "--order", "2", "--level", "2", "-o", d.file("s.h5")});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("negative directional albedo of -0.5"), std::string::npos) << r.err;

  // CSV samples, all negative: the fit warns, and refuses under --strict.
  {
    std::ofstream o(d.file("samples.csv"));
    o << "theta_i,phi_i,theta_r,phi_r,value\n";
    for (int ti = 0; ti < 90; ti += 10)
      for (int tr = 0; tr < 90; tr += 10)
        for (int p = 0; p < 360; p += 45) o << ti << ",0," << tr << "," << p << ",-0.1\n";
  }
  r = run_cli({"fit", d.file("samples.csv"), "--order", "2", "--level", "2", "--isotropic", "-o", d.file("t.h5"), "--strict"});
  EXPECT_EQ(r.exit_code, kExitInput) << r.err;
  r = run_cli({"fit", d.file("samples.csv"), "--order", "2", "--level", "2", "--isotropic", "-o", d.file("t.h5")});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("non-physical"), std::string::npos) << r.err;

  // A LUT of the fitted spectrum: lut warns (strict: nothing written); albedo says NON-PHYSICAL, not "passes".
  r = run_cli({"lut", d.file("s.h5"), "--level", "2", "--order", "2", "-o", d.file("l.h5"), "--strict"});
  EXPECT_EQ(r.exit_code, kExitInput) << r.err;
  EXPECT_FALSE(exists(d.file("l.h5")));
  r = run_cli({"lut", d.file("s.h5"), "--level", "2", "--order", "2", "-o", d.file("l.h5")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("non-physical"), std::string::npos) << r.err;
  r = run_cli({"albedo", d.file("l.h5")});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.find("passes the white furnace"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("max -0.5"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("NON-PHYSICAL (negative albedo)"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("negative directional albedo of -0.5"), std::string::npos) << r.err;
  r = run_cli({"albedo", d.file("l.h5"), "--strict"});
  EXPECT_EQ(r.exit_code, kExitInput) << r.err;
  EXPECT_EQ(r.out, "");
}

}  // namespace
