// icobrdf modes: values against independent closed forms (paper Table 1, eq. 13 written out), the JSON and
// text layouts of the contract, and error exits.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::run_cli;
using icobrdf::test::TempDir;

// Closed forms of O(1) values evaluated two ways in double; JSON carries round-trip doubles.
constexpr double kTol = 1e-13;
constexpr double kDeg = M_PI / 180.0;

std::string write(const TempDir& dir, const std::string& name, const std::string& text) {
  const std::string path = dir.file(name);
  std::ofstream(path) << text;
  return path;
}

struct Pair {
  double ti, pi, tr, pr;  // degrees
};

const std::vector<Pair> kPairs = {{30, 0, 45, 180}, {0, 0, 90, 10}, {89.5, -170, 12.25, 370}, {60, 45, 60, 45}};

std::string pairs_csv() {
  std::ostringstream s;
  s << "theta_i,phi_i,theta_r,phi_r\n";
  for (const auto& p : kPairs) s << p.ti << "," << p.pi << "," << p.tr << "," << p.pr << "\n";
  return s.str();
}

TEST(CliModes, IsotropicValuesMatchTable1) {
  TempDir tmp;
  const auto r = run_cli({"modes", "--order", "4", "--isotropic", "--at", write(tmp, "p.csv", pairs_csv()), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("order").get<int>(), 4);
  EXPECT_TRUE(j.at("isotropic").get<bool>());
  const auto idx = j.at("indices").get<std::vector<std::vector<int>>>();
  ASSERT_EQ(idx.size(), 14u);  // Table 2
  const std::vector<std::vector<int>> table2 = {{0, 0, 0}, {1, 1, 1}, {2, 0, 0}, {2, 2, 0}, {2, 2, 2},
                                                {3, 1, 1}, {3, 3, 1}, {3, 3, 3}, {4, 0, 0}, {4, 2, 0},
                                                {4, 2, 2}, {4, 4, 0}, {4, 4, 2}, {4, 4, 4}};
  EXPECT_EQ(idx, table2);
  const auto values = j.at("values").get<std::vector<std::vector<double>>>();
  ASSERT_EQ(values.size(), kPairs.size());
  for (size_t r = 0; r < kPairs.size(); ++r) {
    ASSERT_EQ(values[r].size(), 14u);
    // Table 1 in a = sin(theta_i/2), b = sin(theta_r/2), d = phi_i - phi_r.
    const double a = std::sin(kPairs[r].ti * kDeg / 2), b = std::sin(kPairs[r].tr * kDeg / 2);
    const double d = (kPairs[r].pi - kPairs[r].pr) * kDeg, s2 = std::sqrt(2.0);
    EXPECT_NEAR(values[r][0], 1 / (2 * M_PI), kTol);
    EXPECT_NEAR(values[r][1], 2 * s2 / M_PI * a * b * std::cos(d), kTol);
    EXPECT_NEAR(values[r][3], 3 / (2 * M_PI) * (4 * a * a - 1) * (4 * b * b - 1), kTol);
    EXPECT_NEAR(values[r][7], 16 * s2 / M_PI * std::pow(a * b, 3) * std::cos(3 * d), kTol);
    EXPECT_NEAR(values[r][10], 4 * std::sqrt(15.0) / M_PI * a * a * b * b * (4 * a * a + 4 * b * b - 3) * std::cos(2 * d),
                kTol);
    EXPECT_NEAR(values[r][13], 40 * s2 / M_PI * std::pow(a * b, 4) * std::cos(4 * d), kTol);
  }
}

TEST(CliModes, GeneralModesIndicesAndValues) {
  TempDir tmp;
  const auto r = run_cli({"modes", "--order", "2", "--at", write(tmp, "p.csv", pairs_csv()), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_FALSE(j.at("isotropic").get<bool>());
  const auto idx = j.at("indices").get<std::vector<std::vector<int>>>();
  ASSERT_EQ(idx.size(), 21u);  // M(M+1)/2, M = 6
  // Library order: pairs (a <= b) of ANSI indices, b ascending then a: first (K_0^0, K_0^0), (K_0^0, K_1^-1).
  EXPECT_EQ(idx[0], (std::vector<int>{0, 0, 0, 0}));
  EXPECT_EQ(idx[1], (std::vector<int>{0, 0, 1, -1}));
  EXPECT_EQ(idx[5], (std::vector<int>{1, 1, 1, 1}));
  const auto values = j.at("values").get<std::vector<std::vector<double>>>();
  for (size_t row = 0; row < kPairs.size(); ++row) {
    const auto& p = kPairs[row];
    const double ri = std::sqrt(2.0) * std::sin(p.ti * kDeg / 2), rr = std::sqrt(2.0) * std::sin(p.tr * kDeg / 2);
    // H(K_0^0, K_0^0) = K_0^0 K_0^0 = 1/(2 pi); H(K_1^1, K_1^1) = (2/pi) rho_i rho_r cos(phi_i) cos(phi_r) (eq. 19).
    EXPECT_NEAR(values[row][0], 1 / (2 * M_PI), kTol);
    EXPECT_NEAR(values[row][5], 2 / M_PI * ri * rr * std::cos(p.pi * kDeg) * std::cos(p.pr * kDeg), kTol);
    // H(K_0^0, K_1^-1) = [K_0^0(i) K_1^-1(r) + K_1^-1(i) K_0^0(r)] / sqrt(2), K_1^-1 = sqrt(2/pi) rho sin(phi).
    const double k00 = 1 / std::sqrt(2 * M_PI);
    const double expect = (k00 * std::sqrt(2 / M_PI) * rr * std::sin(p.pr * kDeg) +
                           std::sqrt(2 / M_PI) * ri * std::sin(p.pi * kDeg) * k00) / std::sqrt(2.0);
    EXPECT_NEAR(values[row][1], expect, kTol);
  }
}

TEST(CliModes, HemisphereBasisAndTextOutput) {
  TempDir tmp;
  const auto dirs = write(tmp, "d.csv", "theta,phi\n0,0\n90,30\n40,-100\n");
  const auto r = run_cli({"modes", "--order", "2", "--hemisphere", "--at", dirs, "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto idx = j.at("indices").get<std::vector<std::vector<int>>>();
  const std::vector<std::vector<int>> ansi = {{0, 0}, {1, -1}, {1, 1}, {2, -2}, {2, 0}, {2, 2}};
  EXPECT_EQ(idx, ansi);
  const auto values = j.at("values").get<std::vector<std::vector<double>>>();
  const double th[] = {0, 90, 40}, ph[] = {0, 30, -100};
  for (int row = 0; row < 3; ++row) {
    const double rho = std::sqrt(2.0) * std::sin(th[row] * kDeg / 2), phi = ph[row] * kDeg;
    // Eq. (13): K_0^0 = 1/sqrt(2 pi), K_1^{+-1} = sqrt(2/pi) rho {cos, sin}, K_2^0 = sqrt(3/pi)(2rho^2-1)/sqrt(2),
    // K_2^{+-2} = sqrt(3/pi) rho^2 {cos, sin}(2 phi).
    const double expect[] = {1 / std::sqrt(2 * M_PI),
                             std::sqrt(2 / M_PI) * rho * std::sin(phi),
                             std::sqrt(2 / M_PI) * rho * std::cos(phi),
                             std::sqrt(3 / M_PI) * rho * rho * std::sin(2 * phi),
                             std::sqrt(3 / M_PI) * (2 * rho * rho - 1) / std::sqrt(2.0),
                             std::sqrt(3 / M_PI) * rho * rho * std::cos(2 * phi)};
    for (int k = 0; k < 6; ++k) EXPECT_NEAR(values[static_cast<size_t>(row)][static_cast<size_t>(k)], expect[k], kTol);
  }
  // Text: a comment, the CSV header, then rows x modes lines "row,n,l,value".
  const auto t = run_cli({"modes", "--order", "2", "--hemisphere", "--at", dirs});
  ASSERT_EQ(t.exit_code, 0) << t.err;
  std::istringstream in(t.out);
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(in, line)) lines.push_back(line);
  ASSERT_EQ(lines.size(), 2u + 3 * 6);
  EXPECT_EQ(lines[0].rfind("#", 0), 0u);
  EXPECT_EQ(lines[1], "row,n,l,value");
  EXPECT_EQ(lines[2].rfind("0,0,0,", 0), 0u);
  EXPECT_NEAR(std::stod(lines[2].substr(6)), 1 / std::sqrt(2 * M_PI), kTol);
  EXPECT_EQ(lines.back().rfind("2,2,2,", 0), 0u);
}

TEST(CliModes, OrderZero) {
  TempDir tmp;
  const auto r = run_cli({"modes", "--order", "0", "--isotropic", "--at", write(tmp, "p.csv", pairs_csv()), "--json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j.at("indices").size(), 1u);
  EXPECT_NEAR(j.at("values")[2][0].get<double>(), 1 / (2 * M_PI), kTol);
}

TEST(CliModes, ErrorExits) {
  TempDir tmp;
  const auto pairs = write(tmp, "p.csv", pairs_csv());
  for (const char* order : {"-1", "129"}) {
    const auto r = run_cli({"modes", "--order", order, "--at", pairs});
    EXPECT_EQ(r.exit_code, 2) << order;  // ArgumentError
    EXPECT_TRUE(r.out.empty());
    EXPECT_NE(r.err.find("--order"), std::string::npos) << r.err;
  }
  EXPECT_EQ(run_cli({"modes", "--order", "2", "--isotropic", "--hemisphere", "--at", pairs}).exit_code, 2);
  EXPECT_EQ(run_cli({"modes", "--order", "2"}).exit_code, 2);  // --at is required
  // Malformed input: line-numbered InputError, exit 3, nothing on stdout.
  const auto bad = write(tmp, "bad.csv", "theta_i,phi_i,theta_r,phi_r\n10,0,20,0\n10,0,abc,0\n");
  const auto r = run_cli({"modes", "--order", "2", "--at", bad});
  EXPECT_EQ(r.exit_code, 3);
  EXPECT_TRUE(r.out.empty());
  EXPECT_NE(r.err.find(":3"), std::string::npos) << r.err;
  const auto below = write(tmp, "below.csv", "theta_i,phi_i,theta_r,phi_r\n95,0,20,0\n");
  EXPECT_EQ(run_cli({"modes", "--order", "2", "--at", below}).exit_code, 3);
  EXPECT_EQ(run_cli({"modes", "--order", "2", "--hemisphere", "--at", pairs}).exit_code, 3);  // wrong columns
  // A missing file is reported by the CSV reader (input error 3, or file-system error 5).
  const int missing = run_cli({"modes", "--order", "2", "--at", tmp.file("missing.csv")}).exit_code;
  EXPECT_TRUE(missing == 3 || missing == 5) << missing;
  // The general modes at order 128 (35 million per row) exceed the output limit: UnsupportedError.
  const auto big = run_cli({"modes", "--order", "128", "--at", pairs});
  EXPECT_EQ(big.exit_code, 4);
  EXPECT_TRUE(big.out.empty());
}

}  // namespace ICOBRDF_UNITY_ID
