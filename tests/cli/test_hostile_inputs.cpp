// Runs every row of tests/cli/hostile_inputs.tsv (issue #19's table of hostile inputs, covering its four
// classes): the expected exit code and message, and for every row the common promises: no exit 70 or 134,
// one stderr line on failure, no internal function named, no out.* file left by a failing command.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf::test {
namespace ICOBRDF_UNITY_ID {

namespace fs = std::filesystem;

struct Row {
  int line = 0;
  std::string cls;
  int exit_code = 0;
  std::string pattern;
  std::string args;
};

std::vector<Row> read_table() {
  std::ifstream in(std::string(ICOBRDF_SOURCE_DIR) + "/tests/cli/hostile_inputs.tsv");
  std::vector<Row> rows;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (text.empty() || text[0] == '#') continue;
    std::vector<std::string> f;
    std::stringstream ss(text);
    std::string field;
    while (std::getline(ss, field, '\t')) f.push_back(field);
    if (f.size() != 4) {
      ADD_FAILURE() << "hostile_inputs.tsv line " << line << ": expected 4 tab-separated fields, found " << f.size();
      continue;
    }
    rows.push_back({line, f[0], std::stoi(f[1]), f[2], f[3]});
  }
  return rows;
}

void write(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

std::string replace_all(std::string s, const std::string& from, const std::string& to) {
  for (size_t p = s.find(from); p != std::string::npos; p = s.find(from, p + to.size())) s.replace(p, from.size(), to);
  return s;
}

// The fixtures every row may name, written once into `d`.
void write_fixtures(const std::string& d) {
  fs::create_directories(d + "/folder");
  ASSERT_EQ(::mkfifo((d + "/fifo").c_str(), 0600), 0);
  fs::create_symlink(d + "/fifo", d + "/link-to-fifo");
  write(d + "/pairs.csv", "theta_i,phi_i,theta_r,phi_r\n10,0,20,180\n");
  write(d + "/mirror-pairs.csv", "theta_i,phi_i,theta_r,phi_r\n0,0,0,0\n");
  write(d + "/nan-pairs.csv", "theta_i,phi_i,theta_r,phi_r\n10,0,nan,180\n");
  write(d + "/bad-angle-pairs.csv", "theta_i,phi_i,theta_r,phi_r\n10,0,95,180\n");
  write(d + "/field.csv", "theta_i,phi_i,theta_r,phi_r\n10,0," + std::string(1000001, '7') + ",180\n");
  write(d + "/neg.txt", "1,1,0,0,0,0,0,-1\n");
  write(d + "/mixed.txt", "1,1,0,0,0,0,0,1\n1,1,2,0,0,0,0,3\n");  // f changes sign across the hemisphere
  write(d + "/absurd-azimuth-pairs.csv", "theta_i,phi_i,theta_r,phi_r\n10,0,20,1e308\n");
  {
    std::ofstream o(d + "/nan.csv");
    o << "theta_i,phi_i,theta_r,phi_r,value\n";
    for (int ti = 0; ti < 90; ti += 10)
      for (int tr = 0; tr < 90; tr += 10) o << ti << ",0," << tr << ",180," << (ti == 40 && tr == 40 ? "nan" : "0.3") << "\n";
  }
  const std::string material = "\n[[material]]\nname = \"a\"\nsource = \"model:lambert:albedo=0.5\"\n";
  write(d + "/scene.toml", "[bank]\nlevel = 1\nlevels = [1]\norder_max = 2\ntarget = 0.01\n" + material +
                               "\n[[material]]\nname = \"b\"\nsource = \"model:lambert:albedo=0.8\"\n");
  write(d + "/store-lut-6.toml", "[bank]\nlevel = 6\nlevels = [2]\norder_max = 4\nstore_lut = true\n" + material);
  write(d + "/levels-5-2.toml", "[bank]\nlevels = [5, 2]\n" + material);
  write(d + "/level-huge.toml", "[bank]\nlevel = 4294967300\n" + material);
  write(d + "/no-material.toml", "[bank]\nlevel = 1\n");
  write(d + "/negative.toml", "[bank]\nlevel = 1\nlevels = [2]\norder_max = 2\n\n[[material]]\nname = \"n\"\nsource = \"scatmech:" + d +
                                  "/neg.txt\"\norder = 2\n");
  std::string lights = "[", cameras = "[";
  for (int k = 0; k < 1001; ++k) lights += (k ? ", [" : "[") + std::to_string(k % 80) + ", 0]";
  for (int k = 0; k < 1000; ++k) cameras += (k ? ", [" : "[") + std::to_string(k % 80) + ", 90]";
  write(d + "/pairs.toml", "[bank]\nlevel = 2\nlevels = [2]\norder_max = 4\n\n[[material]]\nname = \"m\"\nsource = \"model:lambert\"\nlights = " +
                               lights + "]\ncameras = " + cameras + "]\n");
  for (const auto& args : std::vector<std::vector<std::string>>{
           {"bank", "build", d + "/scene.toml", "-o", d + "/bank.h5", "--no-progress"},
           {"lut", "model:lambert", "--level", "2", "--order", "2", "-o", d + "/lut.h5"},
           {"fit", "model:lambert", "--level", "2", "--order", "2", "-o", d + "/spectrum.h5"}}) {
    const auto r = run_cli(args);
    ASSERT_EQ(r.exit_code, 0) << args[0] << ": " << r.err;
  }
}

std::string spec_with_typo() {
  std::string s = "model:";
  for (int k = 1; k <= 7000; ++k) s += (k > 1 ? "+" : "") + std::string(k == 6001 ? "0.0001*lambrt" : "0.0001*lambert");
  return s;
}

TEST(HostileInputs, EveryRowGivesItsExitCodeAndMessage) {
  const auto rows = read_table();
  ASSERT_GE(rows.size(), 60u);
  int per_class[5] = {0, 0, 0, 0, 0};
  const fs::path d = fs::temp_directory_path() / ("icobrdf_hostile_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  write_fixtures(d.string());
  if (HasFatalFailure()) return;
  const std::string spec = spec_with_typo();
  // A snake_case identifier or a Class::member followed by ':'.
  const std::regex function_name("([a-z0-9]+_[a-z0-9_]+|[A-Za-z0-9]+::[A-Za-z0-9_]+): ");
  for (const Row& row : rows) {
    ++per_class[std::stoi(row.cls)];
    std::string args = replace_all(row.args, "{d}", d.string());
    args = replace_all(args, "{o}", (d / "out.h5").string());
    args = replace_all(args, "{png}", (d / "out.png").string());
    std::vector<std::string> argv;
    std::stringstream ss(args);
    for (std::string a; ss >> a;) argv.push_back(a == "{spec7000}" ? spec : a);
    SCOPED_TRACE("hostile_inputs.tsv line " + std::to_string(row.line) + ": icobrdf " + row.args);
    const auto r = run_cli(argv);
    EXPECT_EQ(r.exit_code, row.exit_code) << r.err;
    EXPECT_NE(r.exit_code, 70);
    EXPECT_NE(r.exit_code, 134);
    EXPECT_TRUE(std::regex_search(r.err, std::regex(row.pattern))) << "stderr: " << r.err.substr(0, 400);
    if (r.exit_code != 0) {
      EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err.substr(0, 400);
      EXPECT_LE(r.err.size(), 700u);
      EXPECT_FALSE(std::regex_search(r.err, function_name)) << r.err;
      for (const char* out : {"out.h5", "out.png", "out.csv"}) EXPECT_FALSE(fs::exists(d / out)) << out;
    }
    for (const char* out : {"out.h5", "out.png", "out.csv"}) fs::remove(d / out);
    for (const auto& e : fs::directory_iterator(d))  // no temporary of an atomic write is left
      EXPECT_EQ(e.path().filename().string().find(".tmp-"), std::string::npos) << e.path();
  }
  for (int c = 1; c <= 4; ++c) EXPECT_GE(per_class[c], 10) << "class " << c << " has few rows";
  fs::remove_all(d);
}

}  // namespace
}  // namespace icobrdf::test
