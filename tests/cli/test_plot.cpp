// icobrdf plot: each subcommand writes a valid PNG of the size it reports (PNG signature and IHDR read
// directly from the bytes); bad arguments give one-line errors, a non-zero exit and no file.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf::test {
namespace ICOBRDF_UNITY_ID {

struct PngHeader {
  bool valid = false;
  std::uint32_t width = 0, height = 0;
};

// PNG: 8-byte signature, then the IHDR chunk (length 13, type "IHDR", width and height big-endian).
PngHeader png_header(const std::string& path) {
  const std::string b = slurp(path);
  PngHeader h;
  static const unsigned char kSig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (b.size() < 24 || b.compare(0, 8, std::string(reinterpret_cast<const char*>(kSig), 8)) != 0 || b.compare(12, 4, "IHDR") != 0)
    return h;
  auto be32 = [&](std::size_t o) {
    return (std::uint32_t(std::uint8_t(b[o])) << 24) | (std::uint32_t(std::uint8_t(b[o + 1])) << 16) |
           (std::uint32_t(std::uint8_t(b[o + 2])) << 8) | std::uint32_t(std::uint8_t(b[o + 3]));
  };
  h.valid = be32(8) == 13;
  h.width = be32(16);
  h.height = be32(20);
  return h;
}

bool exists(const std::string& p) { return access(p.c_str(), F_OK) == 0; }

void expect_png_of_reported_size(const CliResult& r, const std::string& path) {
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const PngHeader h = png_header(path);
  ASSERT_TRUE(h.valid) << path;
  EXPECT_EQ(h.width, j.at("width").get<std::uint32_t>());
  EXPECT_EQ(h.height, j.at("height").get<std::uint32_t>());
  EXPECT_GT(h.width, 300u);
  EXPECT_GT(h.height, 200u);
}

void expect_one_line_error(const CliResult& r, int code) {
  EXPECT_EQ(r.exit_code, code) << r.err;
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
}

TEST(CliPlot, BasisWritesTheGridAndOneFilePerFunction) {
  TempDir d;
  const auto r = run_cli({"plot", "basis", "--order", "2", "--separate", "-o", d.path, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto files = nlohmann::json::parse(r.out).at("files");
  EXPECT_EQ(files.size(), 1u + 6u);  // basis.png + (2+1)(2+2)/2 functions
  for (const auto& f : files) EXPECT_TRUE(png_header(f.get<std::string>()).valid) << f;
  EXPECT_TRUE(exists(d.file("K_2_-2.png")));
}

TEST(CliPlot, ListsTakeCommasAndOutputTakesAFileOrAFolder) {
  TempDir d;
  // --order 1,2,3 and --order 1 2 3 are the same three columns (plus the model's own).
  for (const auto& orders : {std::vector<std::string>{"1,2,3"}, std::vector<std::string>{"1", "2", "3"}}) {
    std::vector<std::string> args{"plot", "slice", "model:lambert", "--level", "2", "--order"};
    args.insert(args.end(), orders.begin(), orders.end());
    for (const char* a : {"-o", "", "--json"}) args.push_back(a);
    args[args.size() - 2] = d.file("s.png");
    const auto r = run_cli(args);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out).at("columns").get<int>(), 4);
  }
  const auto b = run_cli({"plot", "basis", "--order", "1", "-o", d.file("pyramid.png"), "--json"});
  ASSERT_EQ(b.exit_code, 0) << b.err;
  EXPECT_TRUE(png_header(d.file("pyramid.png")).valid);
  ASSERT_EQ(run_cli({"plot", "curves", "model:ggx:alpha=0.3", "--theta-i", "0,30,60", "--log", "-o", d.file("c.png")}).exit_code, 0);
  EXPECT_TRUE(png_header(d.file("c.png")).valid);
  ASSERT_EQ(run_cli({"plot", "albedo", "model:lambert", "-o", d.file("a.png")}).exit_code, 0);
  EXPECT_TRUE(png_header(d.file("a.png")).valid);
  expect_one_line_error(run_cli({"plot", "curves", "model:lambert", "--theta-i", "0,95", "-o", d.file("x.png")}), 2);
  EXPECT_FALSE(exists(d.file("x.png")));
}

TEST(CliPlot, SliceSpectrumAndSphere) {
  TempDir d;
  expect_png_of_reported_size(
      run_cli({"plot", "slice", "model:retroreflector+0.05*lambert", "--theta-i", "67.5", "--order", "2", "4", "--level", "3",
               "--filter", "hann", "-o", d.file("slice.png"), "--json"}),
      d.file("slice.png"));
  ASSERT_EQ(run_cli({"fit", "model:ggx-aniso:alpha_x=0.3,alpha_y=0.6", "--order", "4", "--level", "3", "-o", d.file("s.h5")}).exit_code, 0);
  const auto rs = run_cli({"plot", "spectrum", d.file("s.h5"), "-o", d.file("spectrum.png"), "--json"});
  expect_png_of_reported_size(rs, d.file("spectrum.png"));
  EXPECT_TRUE(nlohmann::json::parse(rs.out).at("matrix").get<bool>());  // not isotropic: C drawn too
  expect_png_of_reported_size(run_cli({"plot", "sphere", d.file("s.h5"), "--light", "30,90", "--sky", "--size", "96", "-o",
                                       d.file("sphere.png"), "--json"}),
                              d.file("sphere.png"));
  expect_png_of_reported_size(
      run_cli({"plot", "slice", d.file("s.h5"), "--theta-i", "30", "--order", "4", "-o", d.file("slice2.png"), "--json"}),
      d.file("slice2.png"));
}

TEST(CliPlot, BadArgumentsGiveOneLineErrorsAndNoFile) {
  TempDir d;
  const std::string out = d.file("x.png");
  expect_one_line_error(run_cli({"plot", "slice", "model:lambert", "--theta-i", "95", "-o", out}), 2);
  expect_one_line_error(run_cli({"plot", "slice", "model:nonsense", "-o", out}), 2);
  expect_one_line_error(run_cli({"plot", "slice", "model:lambert", "--order", "40", "-o", out}), 2);
  expect_one_line_error(run_cli({"plot", "sphere", "model:lambert", "--light", "45", "-o", out}), 2);
  expect_one_line_error(run_cli({"plot", "sphere", "model:mirror", "--shading", "model", "-o", out}), 2);
  expect_one_line_error(run_cli({"plot", "spectrum", d.file("missing.h5"), "-o", out}), 5);
  expect_one_line_error(run_cli({"plot", "basis", "--order", "3", "-o", d.file("no-such-dir")}), 2);
  EXPECT_FALSE(exists(out));
  // A spectrum file's order bounds the truncation orders.
  ASSERT_EQ(run_cli({"fit", "model:lambert", "--order", "2", "--level", "2", "-o", d.file("l.h5")}).exit_code, 0);
  expect_one_line_error(run_cli({"plot", "slice", d.file("l.h5"), "--order", "4", "-o", out}), 2);
  EXPECT_FALSE(exists(out));
}

TEST(CliPlot, SamplesHalfDiffAzimuthAndStoredValues) {
  TempDir d;
  const std::string ptfe = std::string(ICOBRDF_SOURCE_DIR) + "/tests/data/measured/ptfe532.csv";
  const auto r = run_cli({"plot", "samples", ptfe, "--theta-i", "15,45", "--log", "-o", d.file("s.png"), "--json"});
  expect_png_of_reported_size(r, d.file("s.png"));
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("theta_i").size(), 2u);
  EXPECT_GT(j.at("drawn").get<int>(), 0);
  EXPECT_EQ(j.at("samples").get<int>(), 1824);  // the file's rows (tests/data/measured/README.md), none merged
  expect_one_line_error(run_cli({"plot", "samples", "model:lambert", "-o", d.file("x.png")}), 2);
  EXPECT_FALSE(exists(d.file("x.png")));
  ASSERT_EQ(run_cli({"plot", "halfdiff", "model:ggx:alpha=0.3", "--phi-d", "0", "-o", d.file("hd.png")}).exit_code, 0);
  EXPECT_TRUE(png_header(d.file("hd.png")).valid);
  // A stored spectrum shaded from its values (--shading model) as from its spectrum.
  ASSERT_EQ(run_cli({"fit", "model:lambert", "--order", "2", "--level", "2", "-o", d.file("l.h5")}).exit_code, 0);
  const auto m = run_cli({"plot", "sphere", d.file("l.h5"), "--shading", "model", "--size", "64", "-o", d.file("m.png"), "--json"});
  expect_png_of_reported_size(m, d.file("m.png"));
  // Its slice without --order: the default orders 0, 1, 2, 4, 6, 8 up to its own order 2.
  const auto sl = run_cli({"plot", "slice", d.file("l.h5"), "-o", d.file("sl.png"), "--json"});
  ASSERT_EQ(sl.exit_code, 0) << sl.err;
  EXPECT_EQ(nlohmann::json::parse(sl.out).at("columns").get<int>(), 3);
}

// A tiny scene's bank keeps every point its build reached: the modes' orders and the lobe's grids, drawn as
// error against bytes.
TEST(CliPlot, BytesOfATinyBankMaterial) {
  TempDir d;
  const std::string scene = d.file("s.toml"), bank = d.file("b.h5");
  {
    std::ofstream(scene) << "[bank]\nlevels = [1, 2]\norder_max = 4\nholdout_pairs = 2000\n"
                            "[[material]]\nname = \"ggx\"\nsource = \"model:ggx:alpha=0.3\"\ntarget = 0.05\n";
  }
  ASSERT_EQ(run_cli({"bank", "build", scene, "-o", bank, "--quiet"}).exit_code, 0);
  const auto info = nlohmann::json::parse(run_cli({"bank", "info", bank, "--json"}).out);
  EXPECT_EQ(info.at("materials").at(0).at("candidates").get<std::string>().rfind("icobrdf-candidates 1;", 0), 0u);
  const auto r = run_cli({"plot", "bytes", bank + "#ggx", "-o", d.file("bytes.png"), "--json"});
  expect_png_of_reported_size(r, d.file("bytes.png"));
  const auto j = nlohmann::json::parse(r.out);
  // Orders 0..2 at level 1 and 0..4 at level 2 share their sizes: 5 modes points, and at least the lobe chosen.
  EXPECT_GE(j.at("points").get<int>(), 6);
  EXPECT_EQ(j.at("representations").at(0), "half-angle");
  EXPECT_EQ(j.at("representations").at(1), "modes");
  // The stored lobe's slice without --order: one column of its values.
  const auto sl = run_cli({"plot", "slice", bank + "#ggx", "-o", d.file("sl.png"), "--json"});
  ASSERT_EQ(sl.exit_code, 0) << sl.err;
  EXPECT_EQ(nlohmann::json::parse(sl.out).at("columns").get<int>(), 1);
  // A spectrum file is no bank build's material.
  ASSERT_EQ(run_cli({"fit", "model:lambert", "--order", "0", "--level", "1", "-o", d.file("l.h5")}).exit_code, 0);
  expect_one_line_error(run_cli({"plot", "bytes", d.file("l.h5"), "-o", d.file("x.png")}), 3);
  EXPECT_FALSE(exists(d.file("x.png")));
}

}  // namespace
}  // namespace icobrdf::test
