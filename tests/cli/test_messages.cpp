// Issue #19, class 4 "messages stay one short line": huge input is quoted cut, a source too long to store
// is refused before any fit, no message names an internal function, and every numeric option with a range
// refuses a value outside it (exit 2, one line naming the option) instead of ignoring it.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf::test {
namespace ICOBRDF_UNITY_ID {

constexpr std::size_t kShortLine = 400;  // "icobrdf: error: ", a temp path and one quote cut at 200 characters

void write(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// Exit `code`, stderr one line of under kShortLine characters containing `needle`.
void expect_one_short_line(const CliResult& r, int code, const std::string& needle, const std::string& what) {
  EXPECT_EQ(r.exit_code, code) << what << ": " << r.err.substr(0, 400);
  EXPECT_LT(r.err.size(), kShortLine) << what << ": " << r.err.substr(0, 400);
  ASSERT_FALSE(r.err.empty()) << what;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << what << ": " << r.err.substr(0, 400);
  EXPECT_NE(r.err.find(needle), std::string::npos) << what << ": " << r.err.substr(0, 400);
}

TEST(CliMessages, TypoInA7000TermSpecGivesOneShortLine) {
  TempDir d;
  write(d.file("p.csv"), "theta_i,phi_i,theta_r,phi_r\n10,0,20,180\n");
  std::string spec = "model:";
  for (int k = 0; k < 7000; ++k) spec += (k ? "+" : "") + std::string(k == 6000 ? "lambertt" : "0.001*lambert");  // one argument stays under 128 KiB
  expect_one_short_line(run_cli({"eval", spec, "--at", d.file("p.csv")}), 2, "term 6001 of 7000", "7000-term spec");
}

TEST(CliMessages, HugeCsvFieldGivesOneShortLine) {
  TempDir d;
  write(d.file("p.csv"), "theta_i,phi_i,theta_r,phi_r\n10,0," + std::string(1000000, '2') + "x,180\n");
  expect_one_short_line(run_cli({"eval", "model:lambert", "--at", d.file("p.csv")}), 3, "(1000001 characters)", "1 MB field");
}

// A source longer than a bank stores (one HDF5 attribute of at most 64 KiB) is refused when the scene is
// read: before the first material is fitted, no progress line, no output.
TEST(CliMessages, SourceTooLongToStoreIsRefusedUpFront) {
  TempDir d;
  std::string spec = "model:lambert";
  while (spec.size() <= 65536) spec += "+0.001*lambert";
  write(d.file("s.toml"), "[bank]\nlevels = [1]\n[[material]]\nname = \"first\"\nsource = \"model:lambert\"\n"
                          "[[material]]\nname = \"long\"\nsource = \"" + spec + "\"\n");
  const CliResult r = run_cli({"bank", "build", d.file("s.toml"), "-o", d.file("b.h5")});
  expect_one_short_line(r, 3, "60000", "bank build");
  EXPECT_EQ(r.err.find("[1/2]"), std::string::npos) << r.err;  // nothing was fitted
  EXPECT_FALSE(std::ifstream(d.file("b.h5")).good());
  expect_one_short_line(run_cli({"fit", spec, "--order", "2", "--level", "1", "-o", d.file("f.h5")}), 2, "60000", "fit");
  expect_one_short_line(run_cli({"lut", spec, "--order", "2", "--level", "1", "-o", d.file("f.h5")}), 2, "60000", "lut");
  EXPECT_FALSE(std::ifstream(d.file("f.h5")).good());
}

TEST(CliMessages, UnorderedSceneLevelsAreRefused) {
  TempDir d;
  write(d.file("s.toml"), "[bank]\nlevels = [5, 2]\n[[material]]\nname = \"a\"\nsource = \"model:lambert\"\n");
  expect_one_short_line(run_cli({"bank", "build", d.file("s.toml"), "-o", d.file("b.h5")}), 3, "strictly increasing", "levels");
}

// `plot slice --phi-i inf` said "zernike_radial_all: rho must be in [0, 1], got -nan".
TEST(CliMessages, NonFiniteAnglesNameTheOptionNotAFunction) {
  TempDir d;
  const std::regex function_name("[a-z0-9]+_[a-z0-9_]+:");  // snake_case identifier followed by ':'
  for (const auto& [opt, value] : std::vector<std::pair<std::string, std::string>>{
           {"--phi-i", "inf"}, {"--phi-i", "nan"}, {"--phi-i", "-inf"}, {"--theta-i", "inf"}, {"--theta-i", "nan"}, {"--theta-i", "90"}}) {
    const CliResult r = run_cli({"plot", "slice", "model:lambert", opt, value, "-o", d.file("s.png")});
    expect_one_short_line(r, 2, opt, opt + " " + value);
    EXPECT_FALSE(std::regex_search(r.err, function_name)) << r.err;
  }
}

// Every numeric option with a range, with values just outside it and non-finite ones.
TEST(CliMessages, OutOfRangeOptionsAreRefused) {
  TempDir d;
  write(d.file("p.csv"), "theta_i,phi_i,theta_r,phi_r\n10,0,20,180\n");
  const std::string out = d.file("o.h5"), png = d.file("o.png");
  const std::vector<std::string> sweep = {"bench", "sweep", "--quick", "-q", "-o", out, "--report", d.file("r")};
  struct Case {
    std::vector<std::string> command;  // without the option
    std::string option;
    std::vector<std::string> refused;
  };
  const std::vector<Case> cases = {
      {{"bench", "project"}, "--peak-gflops", {"-5", "0", "nan", "inf", "1e10"}},
      {{"bench", "project"}, "--threads", {"1024", "0", "-1"}},
      {sweep, "--threads", {"1024", "0"}},
      {sweep, "--gram-tol", {"-1", "0", "1", "nan", "inf"}},
      {{"bench", "baselines", "--quick"}, "--threads", {"1024", "0"}},
      {{"bench", "hard-cases", "--quick"}, "--threads", {"1024", "0"}},
      {{"fit", "model:lambert", "-o", out}, "--gram-tol", {"-1", "0", "1", "nan", "inf"}},
      {{"export", d.file("x.h5"), "--format", "scatmech", "-o", d.file("x.csv")}, "--channel", {"-1", "3"}},
      {{"grid"}, "--level", {"-1", "9"}},
      {{"modes", "--at", d.file("p.csv")}, "--order", {"-1", "129"}},
      {{"plot", "slice", "model:lambert", "-o", png}, "--order", {"-1", "33"}},
      {{"plot", "slice", "model:lambert", "-o", png}, "--phi-i", {"361", "-361"}},
      {{"plot", "slice", "model:lambert", "-o", png}, "--theta-i", {"-1"}},
      {{"plot", "sphere", "model:lambert", "-o", png}, "--order", {"-1", "33"}},
      {{"plot", "sphere", "model:lambert", "-o", png}, "--exposure", {"0", "-1", "nan", "inf"}},
      {{"plot", "sphere", "model:lambert", "-o", png}, "--sky-radiance", {"-1", "nan", "inf"}},
      {{"plot", "sphere", "model:lambert", "-o", png}, "--size", {"15", "2049"}},
      {{"plot", "sphere", "model:lambert", "-o", png}, "--light", {"181,0", "-1,0", "nan,0", "45,inf"}},
      {{"plot", "basis", "-o", d.path}, "--panel", {"31", "801"}},
  };
  for (const auto& c : cases)
    for (const auto& v : c.refused) {
      auto args = c.command;
      args.push_back(c.option);
      args.push_back(v);
      const std::string what = args[0] + " " + args[1] + " " + c.option + " " + v;
      expect_one_short_line(run_cli(args), 2, c.option, what);
    }
  EXPECT_FALSE(std::ifstream(out).good());
  EXPECT_FALSE(std::ifstream(png).good());
}

}  // namespace
}  // namespace icobrdf::test
