// Measured sources in `icobrdf bank build`: CSV samples and a MERL table as materials, their errors measured on
// held-out samples that the fits never see (icobrdf/pipeline/held_out.hpp). The files are written here from closed
// forms; the expected split, fit and error are derived independently (the split's hash recomputed, the
// order-0 fit of constant modes being the weighted mean of the training samples).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;
using icobrdf::test::TempDir;
using nlohmann::json;

namespace ICOBRDF_UNITY_ID {

// Sums of a few hundred terms and a 1 x 1 least-squares solve: rounding far below this.
constexpr double kRounding = 1e-12;
// The order-0 fit of a constant table recovers it to rounding (sums over a million weighted samples).
constexpr double kTableRounding = 1e-10;
// Held-out samples: one in five (icobrdf/pipeline/held_out.hpp kHeldOutShare), the scene's holdout_pairs being larger.
constexpr int kHeldOutShare = 5;

// FNV-1a 64-bit and splitmix64's finalizer, as the split is documented (docs/scenes.md).
std::uint64_t splitmix64(std::uint64_t x) {
  std::uint64_t z = x + 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}
std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t h = 1469598103934665603ULL;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ULL;
  }
  return h;
}

struct Row {
  double ti, pi, tr, pr, f;
  int sample;  // index after duplicates are merged
};

// Directions on a lattice of angles (no pair repeated but the one duplicate row appended), values
// rho / pi (1 + 0.1 s_k) with s_k in {-2..2} following the row index: not a function of the directions
// any low order could fit, so the held-out error is that of the training mean.
std::vector<Row> sample_rows() {
  std::vector<Row> rows;
  const double rho = 0.6;
  int k = 0;
  for (double ti : {10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 70.0})
    for (double pi : {0.0, 90.0, 200.0})
      for (double tr : {5.0, 25.0, 45.0, 65.0, 85.0})
        for (double pr : {30.0, 150.0, 270.0}) {
          const double s = (k * 7) % 5 - 2;
          rows.push_back({ti, pi, tr, pr, rho / M_PI * (1.0 + 0.1 * s), k});
          ++k;
        }
  Row dup = rows.front();  // a duplicate: merged into sample 0 with weight 2
  rows.push_back(dup);
  return rows;
}

std::string scene_text(const std::string& source, const std::string& extra, const std::string& target = "0.3") {
  return "[bank]\nlevel = 2\nlevels = [2]\norder_max = 4\ntarget = " + target + "\nmetric = \"f\"\nsampling = \"centre\"\n" + extra +
         "\n[[material]]\nname = \"m\"\nsource = \"" + source + "\"\nisotropic = true\n";
}

std::string pairs_csv(const TempDir& d) {
  const std::string p = d.file("pairs.csv");
  std::ofstream(p) << "theta_i,phi_i,theta_r,phi_r\n0,0,0,0\n35,10,60,200\n80,300,15,45\n";
  return p;
}

TEST(MeasuredBank, CsvSamplesAreFittedOnTheirTrainingPartAndJudgedOnTheHeldOutPart) {
  TempDir d;
  const auto rows = sample_rows();
  const int samples = rows.back().sample == 0 ? static_cast<int>(rows.size()) - 1 : static_cast<int>(rows.size());
  {
    std::ofstream csv(d.file("s.csv"));
    csv.precision(17);
    csv << "theta_i,phi_i,theta_r,phi_r,value\n";
    for (const auto& r : rows) csv << r.ti << "," << r.pi << "," << r.tr << "," << r.pr << "," << r.f << "\n";
  }
  std::ofstream(d.file("scene.toml")) << scene_text(d.file("s.csv"), "");
  const std::string bank = d.file("bank.h5");
  const auto b = run_cli({"bank", "build", d.file("scene.toml"), "-o", bank, "--json"});
  ASSERT_EQ(b.exit_code, 0) << b.out << b.err;

  // The split, derived: the samples with the smallest scrambled indices, one in five of them.
  std::vector<std::pair<std::uint64_t, int>> order;
  const std::uint64_t seed = fnv1a("holdout|m");
  for (int k = 0; k < samples; ++k) order.emplace_back(splitmix64(seed + static_cast<std::uint64_t>(k)), k);
  std::sort(order.begin(), order.end());
  std::vector<bool> held(static_cast<size_t>(samples), false);
  for (int k = 0; k < samples / kHeldOutShare; ++k) held[static_cast<size_t>(order[static_cast<size_t>(k)].second)] = true;
  // Order 0 (one constant mode) fitted by least squares: the mean of the training rows; its error over the
  // held-out rows (a duplicate row counts twice on either side).
  double sum = 0, n = 0;
  for (const auto& r : rows)
    if (!held[static_cast<size_t>(r.sample)]) sum += r.f, n += 1;
  const double mean = sum / n;
  double num = 0, den = 0;
  for (const auto& r : rows)
    if (held[static_cast<size_t>(r.sample)]) num += (mean - r.f) * (mean - r.f), den += r.f * r.f;
  const double expected_l2 = std::sqrt(num / den);
  ASSERT_GT(expected_l2, 0.01);  // the data are not constant: the figure says something
  ASSERT_LT(expected_l2, 0.3);   // and order 0 meets the scene's target

  const json j = json::parse(b.out);
  const json& m = j["materials"][0];
  EXPECT_EQ(m["representation"], "modes") << b.out;  // the half-angle fits refuse scattered samples
  EXPECT_EQ(m["order"], 0) << b.out;
  EXPECT_NEAR(m["error_l2"].get<double>(), expected_l2, kRounding * expected_l2) << b.out;
  EXPECT_NE(b.err.find(std::to_string(samples / kHeldOutShare + (held[0] ? 1 : 0)) + " measured sample(s) held out"), std::string::npos) << b.err;

  // The stored fit is the training mean everywhere: its albedo is pi times that.
  const auto v = icobrdf::test::eval_first_column(bank + "#m", pairs_csv(d));
  ASSERT_EQ(v.size(), 3u);
  for (double x : v) EXPECT_NEAR(x * M_PI, mean * M_PI, kRounding * mean * M_PI);
}

TEST(MeasuredBank, CsvSamplesRefuseLightsAndTooFewSamples) {
  TempDir d;
  std::ofstream(d.file("few.csv")) << "theta_i,phi_i,theta_r,phi_r,value\n10,0,20,0,0.1\n20,0,30,0,0.1\n30,0,40,0,0.1\n40,0,50,0,0.1\n";
  std::ofstream(d.file("few.toml")) << scene_text(d.file("few.csv"), "");
  const auto few = run_cli({"bank", "build", d.file("few.toml"), "-o", d.file("few.h5")});
  EXPECT_NE(few.exit_code, 0);
  EXPECT_NE(few.err.find("held-out split needs at least 5 samples"), std::string::npos) << few.err;
  EXPECT_FALSE(std::ifstream(d.file("few.h5")).good());

  std::ofstream(d.file("lit.toml")) << scene_text(d.file("few.csv"), "") << "lights = [[30, 0]]\ncameras = [[0, 0]]\n";
  const auto lit = run_cli({"bank", "build", d.file("lit.toml"), "-o", d.file("lit.h5")});
  EXPECT_NE(lit.exit_code, 0);
  EXPECT_NE(lit.err.find("no values at the scene's light x camera pairs"), std::string::npos) << lit.err;
  EXPECT_FALSE(std::ifstream(d.file("lit.h5")).good());
}

TEST(MeasuredBank, MerlTableOfALambertianIsRecoveredAndJudgedOnHeldOutBins) {
  TempDir d;
  // MERL layout (icobrdf/io/merl.hpp): dims, then 3 channels x 1,458,000 float64 f / scale_c. Lambertian, albedo
  // rho_c per channel: f = rho_c / pi at every node.
  const double rho[3] = {0.5, 0.6, 0.7}, scale[3] = {1.0 / 1500, 1.15 / 1500, 1.66 / 1500};
  const std::string table = d.file("lambert.binary");
  {
    std::ofstream out(table, std::ios::binary);
    const std::int32_t dims[3] = {90, 90, 180};
    out.write(reinterpret_cast<const char*>(dims), sizeof dims);
    std::vector<double> channel(90 * 90 * 180);
    for (int c = 0; c < 3; ++c) {
      std::fill(channel.begin(), channel.end(), rho[c] / M_PI / scale[c]);
      out.write(reinterpret_cast<const char*>(channel.data()), static_cast<std::streamsize>(channel.size() * sizeof(double)));
    }
  }
  std::ofstream(d.file("scene.toml")) << scene_text("merl:" + table, "representations = [\"modes\"]\n", "1e-6");
  const std::string bank = d.file("bank.h5");
  const auto b = run_cli({"bank", "build", d.file("scene.toml"), "-o", bank, "--json"});
  ASSERT_EQ(b.exit_code, 0) << b.out << b.err;
  EXPECT_NE(b.err.find("4096 measured sample(s) held out"), std::string::npos) << b.err;
  const json m = json::parse(b.out)["materials"][0];
  EXPECT_EQ(m["order"], 0) << b.out;
  EXPECT_LT(m["error_l2"].get<double>(), kTableRounding) << b.out;
  // Every channel's albedo is the table's.
  const auto r = run_cli({"eval", bank + "#m", "--at", pairs_csv(d)});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string header;
  const auto values = icobrdf::test::parse_value_csv(r.out, header);
  ASSERT_EQ(values.size(), 3u) << r.out;
  for (const auto& row : values) {
    ASSERT_EQ(row.size(), 3u) << header;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(row[static_cast<size_t>(c)] * M_PI, rho[c], kTableRounding) << header;
  }
}

}  // namespace ICOBRDF_UNITY_ID
