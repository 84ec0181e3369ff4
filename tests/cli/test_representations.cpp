// Every stored representation through every consumer of a stored material: a bank of three materials, one
// per representation (modes; a half-angle lobe alone; the hybrid of the two), written here in a few
// milliseconds, and each consumer (eval, lut, albedo, sample, plot slice / sphere / halfdiff / curves /
// albedo / spectrum, export scatmech, rgl and merl, bank extract) either agrees with `eval` of the bank within a named tolerance or refuses with a
// non-zero exit and one line naming the representation. The Python objects are enumerated in
// tests/python/module/test_representations.py.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "cli_runner.hpp"
#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/lut_file.hpp"
#include "icobrdf/io/material_eval.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::CliResult;
using test::parse_value_csv;
using test::run_cli;
using test::TempDir;

// eval prints shortest round-trip decimals: the values read back are the doubles computed.
constexpr double kRoundTrip = 0.0;
// A LUT sampled at cell centres holds the same doubles eval computes there, up to the float64 storage.
constexpr double kLutTol = 1e-14;
// SCATMECH rows carry 17 significant digits; the modes summed back agree to rounding of ~15 terms.
constexpr double kScatmechTol = 1e-12;
// The albedo command's quadrature (icobrdf/core/models/albedo_quadrature.hpp) against a 400 x 800 midpoint
// rule of the same values: both resolve these smooth materials far below this.
constexpr double kAlbedoTol = 2e-3;
// Draws of `sample`: the mean weight estimates the albedo without bias; 5 standard errors bound the noise.
constexpr double kSampleSigmas = 5.0;
constexpr int kDraws = 5000;
// A MERL table is constant over each bin (1 degree in theta_d and phi_d, theta_h warped): for materials
// whose values change by well under 1 % per degree, its cosine-weighted relative L2 is far below this.
constexpr double kMerlTol = 0.02;
// The RGL export's own acceptance figure (cosine-weighted relative L2 of the file read back, as
// tests/cli/test_export.cpp), and the same bound on eval of the written file at the fixture's pairs.
constexpr double kRglTol = 0.03;

const char* const kNames[] = {"modes", "lobe", "hybrid"};

// Isotropic modes of order 2 in SCATMECH's span (a reciprocal isotropic f), positive everywhere:
// I_00^0 = 1 / (2 pi) with weight 1 plus small others.
Spectrum fixture_modes() {
  Spectrum s;
  s.order = 2;
  s.isotropic = true;
  s.source = "fixture modes";
  Eigen::VectorXd b = Eigen::VectorXd::Constant(isotropic_mode_count(2), 0.02);
  b[0] = 1.0;
  s.channels = {coefficients_from_ibsss(2, b)};
  return s;
}

// A lobe of the quantity f, isotropic, rank 1: u(t) = 0.3 + 1.5 (1 - t)^2 at 9 nodes of t, v = 1 at 5 x 2
// d nodes, so that f is u interpolated linearly in t = sqrt(theta_h / (pi/2)) wherever the corners are valid.
HalfAngleFactors fixture_lobe() {
  HalfAngleFactors l;
  l.quantity = HalfAngleQuantity::F;
  l.isotropic = true;
  l.n_t = 9;
  l.n_phi_h = 1;
  l.n_theta_d = 5;
  l.n_phi_d = 2;
  l.rank = 1;
  RowMatrixXd u(l.n_t, 1), v = RowMatrixXd::Ones(l.n_theta_d * l.n_phi_d, 1);
  for (int k = 0; k < l.n_t; ++k) {
    const double t = static_cast<double>(k) / (l.n_t - 1);
    u(k, 0) = 0.3 + 1.5 * (1 - t) * (1 - t);
  }
  l.u = {u};
  l.v = {v};
  return l;
}

std::map<std::string, MaterialRecord> fixture_records() {
  std::map<std::string, MaterialRecord> out;
  MaterialRecord modes;
  modes.name = "modes";
  modes.spectrum = fixture_modes();
  MaterialRecord lobe;
  lobe.name = "lobe";
  lobe.spectrum.order = 0;
  lobe.spectrum.isotropic = true;
  lobe.spectrum.source = "fixture lobe";
  lobe.spectrum.channels = {Eigen::MatrixXd::Zero(1, 1)};
  lobe.lobe = fixture_lobe();
  MaterialRecord hybrid = modes;
  hybrid.name = "hybrid";
  hybrid.lobe = fixture_lobe();
  out["modes"] = modes;
  out["lobe"] = lobe;
  out["hybrid"] = hybrid;
  return out;
}

struct Pairs {
  RowMatrix3d wi, wr;
  std::string csv;  // theta_i,phi_i,theta_r,phi_r in degrees
};

// Pairs with both polar angles below 30 degrees: all their interpolation corners are above the horizon.
Pairs fixture_pairs(int n) {
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> th(0.0, 30.0), ph(-180.0, 180.0);
  Pairs p;
  p.wi.resize(n, 3);
  p.wr.resize(n, 3);
  p.csv = "theta_i,phi_i,theta_r,phi_r\n";
  constexpr double kRad = M_PI / 180;
  for (int r = 0; r < n; ++r) {
    const double a = th(g), b = ph(g), c = th(g), d = ph(g);
    p.wi.row(r) = direction_from_angles(a * kRad, b * kRad).transpose();
    p.wr.row(r) = direction_from_angles(c * kRad, d * kRad).transpose();
    char line[128];
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g\n", a, b, c, d);
    p.csv += line;
  }
  return p;
}

struct Fixture {
  TempDir dir;
  std::string bank, pairs_csv;
  std::map<std::string, MaterialRecord> records = fixture_records();
  Pairs pairs = fixture_pairs(64);
  Fixture() {
    bank = dir.file("bank.h5");
    BankContents b;
    for (const auto& [name, rec] : records) b.materials.push_back(rec);
    write_bank(bank, b);
    pairs_csv = dir.file("pairs.csv");
    std::ofstream(pairs_csv) << pairs.csv;
  }
  std::string ref(const std::string& name) const { return bank + "#" + name; }
  Eigen::VectorXd expected(const std::string& name, const RowMatrix3d& wi, const RowMatrix3d& wr) const {
    const MaterialRecord& r = records.at(name);
    return evaluate_material(r.spectrum, r.lobe, wi, wr).col(0);
  }
};

const Fixture& fixture() {
  static const Fixture f;
  return f;
}

// `eval SOURCE --at the pairs` (first column); fails the test when the command fails.
std::vector<double> eval_values(const std::string& source) {
  const CliResult r = run_cli({"eval", source, "--at", fixture().pairs_csv});
  EXPECT_EQ(r.exit_code, 0) << source << ": " << r.err;
  std::string header;
  std::vector<double> v;
  for (const auto& row : parse_value_csv(r.out, header)) v.push_back(row.at(0));
  return v;
}

// A refusal: exit `code`, nothing on stdout, one line on stderr naming the material and `what`.
void expect_refusal(const CliResult& r, int code, const std::string& name, const std::string& what) {
  EXPECT_EQ(r.exit_code, code) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("#" + name), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
}

// Midpoint-rule directional albedo int f(w_i, w_r) cos(theta_r) dw_r of the stored material at theta_i.
double quadrature_albedo(const std::string& name, double theta_i) {
  constexpr int kTheta = 400, kPhi = 800;
  RowMatrix3d wi(kTheta * kPhi, 3), wr(kTheta * kPhi, 3);
  Eigen::VectorXd weight(kTheta * kPhi);
  const Eigen::Vector3d in = direction_from_angles(theta_i, 0.0);
  for (int a = 0; a < kTheta; ++a)
    for (int b = 0; b < kPhi; ++b) {
      const double t = (a + 0.5) * (M_PI / 2) / kTheta, p = (b + 0.5) * 2 * M_PI / kPhi;
      const int r = a * kPhi + b;
      wi.row(r) = in.transpose();
      wr.row(r) = direction_from_angles(t, p).transpose();
      weight[r] = std::cos(t) * std::sin(t) * (M_PI / 2 / kTheta) * (2 * M_PI / kPhi);
    }
  return fixture().expected(name, wi, wr).dot(weight);
}

// eval of every representation gives evaluate_material's doubles (the one material abstraction), and the
// lobe alone matches its definition: u interpolated linearly in t = sqrt(2 theta_h / pi) (v = 1).
TEST(Representations, EvalOfEveryRepresentation) {
  const Fixture& f = fixture();
  for (const std::string name : kNames) {
    const std::vector<double> got = eval_values(f.ref(name));
    const Eigen::VectorXd want = f.expected(name, f.pairs.wi, f.pairs.wr);
    ASSERT_EQ(got.size(), static_cast<size_t>(want.size())) << name;
    for (size_t r = 0; r < got.size(); ++r) EXPECT_NEAR(got[r], want[static_cast<Eigen::Index>(r)], kRoundTrip) << name << " " << r;
  }
  constexpr double kLobeTol = 1e-12;  // linear interpolation recomputed here; rounding only
  const HalfAngleFactors l = fixture_lobe();
  const Eigen::VectorXd lobe = f.expected("lobe", f.pairs.wi, f.pairs.wr);
  for (Eigen::Index r = 0; r < lobe.size(); ++r) {
    const Eigen::Vector3d h = (f.pairs.wi.row(r) + f.pairs.wr.row(r)).normalized();
    const double x = std::sqrt(std::acos(std::min(1.0, h.z())) / (M_PI / 2)) * (l.n_t - 1);
    const int k = std::min(static_cast<int>(x), l.n_t - 2);
    const double want = l.u[0](k, 0) + (x - k) * (l.u[0](k + 1, 0) - l.u[0](k, 0));
    EXPECT_NEAR(lobe[r], want, kLobeTol) << r;
  }
}

// lut --sampling centre: entry (i, j) is f at cells i and j's directions.
TEST(Representations, LutOfEveryRepresentation) {
  const Fixture& f = fixture();
  for (const std::string name : kNames) {
    const std::string out = f.dir.file("lut-" + name + ".h5");
    const CliResult r = run_cli({"lut", f.ref(name), "--level", "2", "--sampling", "centre", "--order", "2", "-o", out});
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    const auto [grid, rec] = read_lut_file(out);
    const Eigen::Index n = grid->directions.rows();
    ASSERT_EQ(rec.lut.at(0).rows(), n);
    RowMatrix3d wi(n * n, 3), wr(n * n, 3);
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = 0; j < n; ++j) {
        wi.row(i * n + j) = grid->directions.row(i);
        wr.row(i * n + j) = grid->directions.row(j);
      }
    const Eigen::VectorXd want = f.expected(name, wi, wr);
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index j = 0; j < n; ++j)
        EXPECT_NEAR(rec.lut[0](i, j), want[i * n + j], kLutTol * (1 + std::abs(want[i * n + j]))) << name << " " << i << " " << j;
  }
}

// albedo and sample: both integrate the material's values; against a midpoint rule of evaluate_material.
TEST(Representations, AlbedoAndSampleOfEveryRepresentation) {
  const Fixture& f = fixture();
  constexpr double kThetaDeg = 20.0;
  for (const std::string name : kNames) {
    const double want = quadrature_albedo(name, kThetaDeg * M_PI / 180);
    const CliResult a = run_cli({"albedo", f.ref(name), "--black-sky", "20", "--json"});
    ASSERT_EQ(a.exit_code, 0) << name << ": " << a.err;
    const double got = nlohmann::json::parse(a.out)["black_sky"][0]["albedo"][0].get<double>();
    EXPECT_NEAR(got, want, kAlbedoTol * want) << name;

    const CliResult s = run_cli({"sample", f.ref(name), "--theta-i", "20", "-n", std::to_string(kDraws), "--seed", "3"});
    ASSERT_EQ(s.exit_code, 0) << name << ": " << s.err;
    std::string header;
    const auto rows = parse_value_csv(s.out, header);
    ASSERT_EQ(rows.size(), static_cast<size_t>(kDraws));
    double sum = 0, sum2 = 0;
    for (const auto& row : rows) {
      sum += row.at(3);
      sum2 += row.at(3) * row.at(3);
    }
    const double mean = sum / kDraws, sd = std::sqrt(std::max(0.0, sum2 / kDraws - mean * mean));
    EXPECT_NEAR(mean, want, kSampleSigmas * sd / std::sqrt(kDraws) + 1e-12) << name;
  }
}

// Pictures: slice, sphere, halfdiff, curves and albedo draw every representation from its values; the
// coefficient plot takes modes alone and refuses a material with a lobe.
TEST(Representations, PlotsOfEveryRepresentation) {
  const Fixture& f = fixture();
  for (const std::string name : kNames) {
    for (const std::string kind : {"slice", "sphere", "halfdiff", "curves", "albedo"}) {
      const std::string out = f.dir.file(kind + "-" + name + ".png");
      const CliResult r = run_cli({"plot", kind, f.ref(name), "-o", out});
      EXPECT_EQ(r.exit_code, 0) << kind << " " << name << ": " << r.err;
      EXPECT_FALSE(test::slurp(out).empty()) << kind << " " << name;
    }
    const std::string out = f.dir.file("spectrum-" + name + ".png");
    const CliResult r = run_cli({"plot", "spectrum", f.ref(name), "-o", out});
    if (name == "modes") {
      EXPECT_EQ(r.exit_code, 0) << r.err;
    } else {
      expect_refusal(r, 4, name, name == "lobe" ? "is a half-angle lobe (no modes)" : "is a hybrid of modes and a half-angle lobe");
      EXPECT_TRUE(test::slurp(out).empty());
    }
  }
}

// export scatmech: the modes read back as a SOURCE give eval's values; a lobe or a hybrid is refused in one
// line (never its modes part written as the material, never an f = 0 file), with or without --isotropic.
TEST(Representations, ScatmechExportOfEveryRepresentation) {
  const Fixture& f = fixture();
  for (const std::string name : kNames) {
    const std::string out = f.dir.file("scatmech-" + name + ".csv");
    for (const bool iso : {false, true}) {
      std::vector<std::string> args = {"export", f.ref(name), "--format", "scatmech", "-o", out};
      if (iso) args.push_back("--isotropic");
      const CliResult r = run_cli(args);
      if (name != "modes") {
        expect_refusal(r, 4, name, "the SCATMECH format stores Zernike modes only");
        EXPECT_TRUE(test::slurp(out).empty());
        continue;
      }
      ASSERT_EQ(r.exit_code, 0) << r.err;
      const std::vector<double> back = eval_values("scatmech:" + out), want = eval_values(f.ref(name));
      ASSERT_EQ(back.size(), want.size());
      for (size_t k = 0; k < back.size(); ++k) EXPECT_NEAR(back[k], want[k], kScatmechTol * std::abs(want[k])) << k;
    }
  }
}

// export merl and bank extract: the file read back against eval of the bank. A MERL table costs about 3 s
// to write and read back, so it is exported for the hybrid alone (modes and lobe together, through the same
// open_source as the other two); the export of lobes and of modes alone is tests/cli/test_export.cpp's.
TEST(Representations, MerlExportAndExtractOfEveryRepresentation) {
  const Fixture& f = fixture();
  for (const std::string name : kNames) {
    const std::vector<double> want = eval_values(f.ref(name));
    const std::string merl = f.dir.file(name + ".binary");
    if (name == "hybrid") {
      const CliResult r = run_cli({"export", f.ref(name), "--format", "merl", "-o", merl, "--json"});
      ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
      const std::vector<double> back = eval_values(merl);
      ASSERT_EQ(back.size(), want.size());
      double num = 0, den = 0;
      for (size_t k = 0; k < back.size(); ++k) {
        num += (back[k] - want[k]) * (back[k] - want[k]);
        den += want[k] * want[k];
      }
      EXPECT_LT(std::sqrt(num / den), kMerlTol) << name;
    }
    const std::string extracted = f.dir.file("extract-" + name + ".h5");
    const CliResult e = run_cli({"bank", "extract", f.ref(name), "-o", extracted});
    ASSERT_EQ(e.exit_code, 0) << name << ": " << e.err;
    const std::vector<double> again = eval_values(extracted + "#" + name);
    ASSERT_EQ(again.size(), want.size());
    for (size_t k = 0; k < want.size(); ++k) EXPECT_EQ(again[k], want[k]) << name << " " << k;
  }
}

// export rgl: every representation written as an RGL .bsdf (through open_source, like merl), the file read
// back by the RGL reader and evaluated at the fixture's pairs against eval of the bank (cosine weighted, as
// the export's own figure, which is checked too).
TEST(Representations, RglExportOfEveryRepresentation) {
  const Fixture& f = fixture();
  for (const std::string name : kNames) {
    const std::string out = f.dir.file(name + ".bsdf");
    const CliResult r = run_cli({"export", f.ref(name), "--format", "rgl", "-o", out, "--json"});
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
    EXPECT_LE(nlohmann::json::parse(r.out)["cosine_rel_l2"].get<double>(), kRglTol) << name;
    const std::vector<double> back = eval_values(out), want = eval_values(f.ref(name));
    ASSERT_EQ(back.size(), want.size()) << name;
    double num = 0, den = 0;
    for (size_t k = 0; k < back.size(); ++k) {
      const auto row = static_cast<Eigen::Index>(k);
      const double c = f.pairs.wi(row, 2) * f.pairs.wr(row, 2);  // cos(theta_i) cos(theta_r)
      num += c * c * (back[k] - want[k]) * (back[k] - want[k]);
      den += c * c * want[k] * want[k];
    }
    EXPECT_LT(std::sqrt(num / den), kRglTol) << name;
  }
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
