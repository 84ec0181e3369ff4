// `icobrdf eval / fit / lut` of RGL materials (FILE.bsdf). The tensor file is assembled here byte by byte
// from the format's description (docs/readers.md), independently of the program's writer.
// The material: one slice theta_i = 0.5 rad, constant vndf (the warp is the identity), 2 x 2 value tables
// whose column u_theta = 0 (microfacet normal = surface normal, i.e. the mirror pair) holds
// rho/pi cos(0.5) per wavelength and whose column u_theta = 1 (normals at 90 degrees: w_r below the horizon)
// holds 0. At the mirror pair of theta_i = 0.5 rad, f = stored value / cos(theta_r) = rho/pi.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;
using icobrdf::test::TempDir;

namespace ICOBRDF_UNITY_ID {

// The stored value is float32: relative rounding 2^-24, plus the degree/radian round trip of the CSV.
constexpr double kFloatTol = 1e-6;

std::string le(std::uint64_t v, int n) {
  std::string s;
  for (int k = 0; k < n; ++k) s.push_back(static_cast<char>(v >> (8 * k)));
  return s;
}
std::string f32(double v) {
  const float f = static_cast<float>(v);
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  return le(u, 4);
}

struct Field {
  std::string name;
  int dtype;  // 1 uint8, 10 float32
  std::vector<std::uint64_t> shape;
  std::string data;
};

std::string tensor_file(const std::vector<Field>& fields) {
  std::string head = std::string("tensor_file\0", 12) + std::string("\x01\x00", 2) + le(fields.size(), 4);
  size_t header_size = head.size();
  for (const auto& f : fields) header_size += 2 + f.name.size() + 2 + 1 + 8 + 8 * f.shape.size();
  std::string body;
  for (const auto& f : fields) {
    head += le(f.name.size(), 2) + f.name + le(f.shape.size(), 2) + std::string(1, static_cast<char>(f.dtype)) +
            le(header_size + body.size(), 8);
    for (auto s : f.shape) head += le(s, 8);
    body += f.data;
  }
  return head + body;
}

std::string lambert_file(const TempDir& d, const std::string& name, const std::vector<double>& nm, const std::vector<double>& rho) {
  const std::uint64_t n = nm.size();
  std::string wl, spectra, ones;
  for (double x : nm) wl += f32(x);
  for (double r : rho)  // rows u_phi = 0, 1; columns u_theta = 0, 1
    spectra += f32(r / M_PI * std::cos(0.5)) + f32(0) + f32(r / M_PI * std::cos(0.5)) + f32(0);
  for (int k = 0; k < 4; ++k) ones += f32(1.0);
  const std::vector<Field> fields = {
      {"description", 1, {4}, "test"},      {"theta_i", 10, {1}, f32(0.5)},     {"phi_i", 10, {1}, f32(0.0)},
      {"ndf", 10, {2, 2}, ones},            {"sigma", 10, {2, 2}, ones},        {"vndf", 10, {1, 1, 2, 2}, ones},
      {"luminance", 10, {1, 1, 2, 2}, ones}, {"wavelengths", 10, {n}, wl},     {"spectra", 10, {1, 1, n, 2, 2}, spectra},
      {"jacobian", 1, {1}, std::string(1, '\0')}};
  std::ofstream(d.file(name), std::ios::binary) << tensor_file(fields);
  return d.file(name);
}

std::string mirror_pairs(const TempDir& d) {
  const double t = 0.5 * 180 / M_PI;
  std::ostringstream s;
  s.precision(17);
  s << "theta_i,phi_i,theta_r,phi_r\n" << t << ",0," << t << ",180\n" << t << ",77," << t << ",257\n";
  std::ofstream(d.file("p.csv")) << s.str();
  return d.file("p.csv");
}

std::vector<std::vector<double>> rows_of(const std::string& out, std::string& header) {
  return icobrdf::test::parse_value_csv(out, header);
}

TEST(CliRgl, EvalGivesRhoOverPiWithWavelengthColumns) {
  TempDir d;
  const std::string f = lambert_file(d, "white.bsdf", {450, 550, 650}, {0.2, 0.4, 0.6}), pairs = mirror_pairs(d);
  auto r = run_cli({"eval", f, "--at", pairs});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string header;
  auto rows = rows_of(r.out, header);
  EXPECT_EQ(header, "f_450nm,f_550nm,f_650nm");
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& row : rows)
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(row[c], 0.2 * (c + 1) / M_PI, kFloatTol * row[c]);
  r = run_cli({"eval", f + "#lambda=500", "--at", pairs});  // halfway between 450 and 550 nm
  ASSERT_EQ(r.exit_code, 0) << r.err;
  rows = rows_of(r.out, header);
  EXPECT_EQ(header, "f_500nm");
  EXPECT_NEAR(rows[0][0], 0.3 / M_PI, kFloatTol);
}

TEST(CliRgl, FitAndLutStoreTheChannelNames) {
  TempDir d;
  const std::string f = lambert_file(d, "four.bsdf", {450, 550, 650, 750}, {0.2, 0.4, 0.6, 0.8}), pairs = mirror_pairs(d);
  // Four wavelengths cannot go into a spectrum (1 or 3 channels): refused with the way out named.
  auto r = run_cli({"fit", f, "--order", "2", "--level", "2", "-o", d.file("x.h5")});
  EXPECT_EQ(r.exit_code, 4) << r.err;
  // stderr: the measured-data note, then the error on one line.
  const size_t error_at = r.err.find("icobrdf: error: ");
  ASSERT_NE(error_at, std::string::npos) << r.err;
  EXPECT_NE(r.err.find("#lambda=", error_at), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin() + static_cast<std::ptrdiff_t>(error_at), r.err.end(), '\n'), 1) << r.err;
  r = run_cli({"fit", f + "#lambda=450/550/650", "--order", "2", "--level", "2", "-o", d.file("x.h5")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli({"eval", d.file("x.h5"), "--at", pairs});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string header;
  rows_of(r.out, header);
  EXPECT_EQ(header, "f_450nm,f_550nm,f_650nm");
  r = run_cli({"lut", f + "#lambda=700", "--level", "2", "--order", "2", "-o", d.file("l.h5")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli({"eval", d.file("l.h5"), "--at", pairs});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  rows_of(r.out, header);
  EXPECT_EQ(header, "f_700nm");
}

TEST(CliRgl, BankBuildAcceptsAnRglSourceAndKeepsItsChannelNames) {
  TempDir d;
  const std::string f = lambert_file(d, "white.bsdf", {450, 550, 650, 750}, {0.2, 0.4, 0.6, 0.8});
  std::ofstream(d.file("scene.toml")) << "[bank]\nlevel = 2\nlevels = [2]\norder_max = 2\ntarget = 0.9\nmetric = \"cosine\"\n"
                                         "[[material]]\nname = \"m\"\nsource = \"" + f + "#lambda=450/550/750\"\n";
  auto r = run_cli({"bank", "build", d.file("scene.toml"), "-o", d.file("bank.h5")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_cli({"eval", d.file("bank.h5") + "#m", "--at", mirror_pairs(d)});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string header;
  rows_of(r.out, header);
  EXPECT_EQ(header, "f_450nm,f_550nm,f_750nm");
}

TEST(CliRgl, MalformedFileIsOneLineInputError) {
  TempDir d;
  const std::string f = lambert_file(d, "cut.bsdf", {450, 550, 650}, {0.2, 0.4, 0.6});
  std::string bytes = icobrdf::test::slurp(f);
  std::ofstream(f, std::ios::binary | std::ios::trunc) << bytes.substr(0, bytes.size() - 3);
  const auto r = run_cli({"eval", f, "--at", mirror_pairs(d)});
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_TRUE(r.out.empty());
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("field 8 'spectra': data of 48 bytes"), std::string::npos) << r.err;
}

}  // namespace ICOBRDF_UNITY_ID
