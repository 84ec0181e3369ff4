// MERL binary reader / writer / lookup (icobrdf/io/merl.hpp). The files are generated here from analytic models.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <random>

#include "icobrdf/core/spectrum/analytic_spectra.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/fit/sample_fit.hpp"
#include "icobrdf/io/merl.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::ScratchDir;

// Round trip of angles through vectors: a few ulps of acos/atan2 near well-conditioned angles.
constexpr double kAngleTol = 1e-9;
// Stored value = f / scale, read back as value * scale: two roundings.
constexpr double kScaleRoundTrip = 4e-16;
// Least-squares recovery of a spectrum in the span from exact node data (cond ~ 1e3, 1e-16 rounding).
constexpr double kFitTol = 1e-10;

// Three channels: Minnaert k = 2, f = 3/(2 pi) cos(ti) cos(tr), times 0.5, 0.7 and 0.9 (distinct per channel,
// so channel order and the per-channel scales are checked).
class RgbMinnaert final : public BrdfModel {
 public:
  int channels() const override { return 3; }
  using BrdfModel::eval;
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override {
    for (Eigen::Index r = 0; r < wi.rows(); ++r) {
      const double zi = std::max(wi(r, 2), 0.0), zr = std::max(wr(r, 2), 0.0);
      const double f = (wi(r, 2) < -kHorizonSlack || wr(r, 2) < -kHorizonSlack) ? 0.0 : 3.0 / (2 * M_PI) * zi * zr;
      for (int c = 0; c < 3; ++c) out(r, c) = (0.5 + 0.2 * c) * f;
    }
  }
  std::string spec() const override { return "test-rgb-minnaert"; }
};

Eigen::Vector3d random_direction(std::mt19937& g) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = 0.02 + 0.98 * u(g), phi = 2 * M_PI * u(g), s = std::sqrt(1 - z * z);
  return {s * std::cos(phi), s * std::sin(phi), z};
}

// One good file shared by the tests of this binary (35 MB; written once).
class MerlFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new ScratchDir();
    write_merl(*dir_ / "ggx.binary", *parse_model("ggx:alpha=0.3"));
    write_merl(*dir_ / "rgb.binary", RgbMinnaert());
  }
  static void TearDownTestSuite() {
    delete dir_;
    dir_ = nullptr;
  }
  static std::string path(const std::string& name) { return *dir_ / name; }
  static ScratchDir* dir_;
};
ScratchDir* MerlFiles::dir_ = nullptr;

TEST(MerlGeometry, HalfDiffRoundTripAndReciprocityFold) {
  std::mt19937 g(1);
  for (int t = 0; t < 2000; ++t) {
    const Eigen::Vector3d wi = random_direction(g), wr = random_direction(g);
    const HalfDiffAngles a = half_diff_from_directions(wi, wr);
    Eigen::Vector3d bi, br;
    directions_from_half_diff(a, bi, br);
    EXPECT_LT((bi - wi).norm(), kAngleTol);
    EXPECT_LT((br - wr).norm(), kAngleTol);
    // Swapping the directions keeps theta_h, theta_d and shifts phi_d by pi.
    const HalfDiffAngles s = half_diff_from_directions(wr, wi);
    EXPECT_NEAR(s.theta_h, a.theta_h, kAngleTol);
    EXPECT_NEAR(s.theta_d, a.theta_d, kAngleTol);
    EXPECT_NEAR(std::cos(s.phi_d), -std::cos(a.phi_d), kAngleTol);
    EXPECT_NEAR(std::sin(s.phi_d), -std::sin(a.phi_d), kAngleTol);
  }
  // Specular configuration: h = normal, so theta_h = 0 and theta_d = theta_i.
  const Eigen::Vector3d wi(std::sin(0.4), 0, std::cos(0.4)), wr(-std::sin(0.4), 0, std::cos(0.4));
  const HalfDiffAngles a = half_diff_from_directions(wi, wr);
  EXPECT_NEAR(a.theta_h, 0.0, kAngleTol);
  EXPECT_NEAR(a.theta_d, 0.4, kAngleTol);
}

// Every node lies in its own bin (floor lookup at a bin centre), with the sqrt mapping of theta_h:
// node theta_h = (pi/2)((i + 1/2)/90)^2 -> 90 sqrt(theta_h/(pi/2)) = i + 1/2.
TEST(MerlGeometry, NodesLieInTheirBins) {
  for (int ih = 0; ih < kMerlThetaHalfRes; ih += 1)
    for (int id = 0; id < kMerlThetaDiffRes; id += 7)
      for (int ip = 0; ip < kMerlPhiDiffRes; ip += 13) {
        const MerlBin b{ih, id, ip};
        Eigen::Vector3d wi, wr;
        directions_from_half_diff(merl_node(b), wi, wr);
        const MerlBin c = merl_bin(wi, wr);
        ASSERT_EQ(c.theta_h, ih);
        ASSERT_EQ(c.theta_d, id);
        ASSERT_EQ(c.phi_d, ip);
        // The swapped pair folds into the same bin.
        const MerlBin d = merl_bin(wr, wi);
        ASSERT_EQ(d.flat(), b.flat()) << ih << " " << id << " " << ip;
      }
  EXPECT_EQ((MerlBin{89, 89, 179}.flat()), kMerlSamplesPerChannel - 1);
  EXPECT_EQ((MerlBin{1, 0, 0}.flat()), 90 * 180);
}

TEST_F(MerlFiles, LookupEqualsModelAtNodesAndChannelScales) {
  const MerlTable t = read_merl(path("rgb.binary"));
  EXPECT_EQ(t.missing_total(), 0);
  const RgbMinnaert m;
  std::mt19937 g(2);
  std::uniform_int_distribution<int> ih(0, 89), id(0, 89), ip(0, 179);
  MerlModel merl(std::make_shared<MerlTable>(t));
  int checked = 0;
  for (int k = 0; k < 3000; ++k) {
    const MerlBin b{ih(g), id(g), ip(g)};
    Eigen::Vector3d wi, wr;
    directions_from_half_diff(merl_node(b), wi, wr);
    if (wi.z() < 0 || wr.z() < 0) continue;
    RowMatrix3d a(1, 3), c(1, 3);
    a.row(0) = wi.transpose();
    c.row(0) = wr.transpose();
    Eigen::MatrixXd want(1, 3), got(1, 3);
    m.eval(a, c, want);
    merl.eval(a, c, got);
    for (int ch = 0; ch < 3; ++ch) {
      EXPECT_NEAR(t.at(ch, b), want(0, ch), kScaleRoundTrip * want(0, ch) + 1e-300);
      EXPECT_EQ(got(0, ch), t.at(ch, b));
    }
    ++checked;
  }
  EXPECT_GT(checked, 1000);
  // Raw stored values: the file holds f / scale_c; check one node by reading its bytes directly.
  std::ifstream in(path("rgb.binary"), std::ios::binary);
  const MerlBin b{30, 20, 10};
  for (int ch = 0; ch < 3; ++ch) {
    in.seekg(12 + 8 * (ch * kMerlSamplesPerChannel + b.flat()));
    double raw = 0;
    in.read(reinterpret_cast<char*>(&raw), 8);  // little-endian host (x86-64, aarch64)
    EXPECT_NEAR(raw * kMerlChannelScale[static_cast<size_t>(ch)], t.at(ch, b), 1e-15 * t.at(ch, b));
  }
}

// GGX: lookup at random pairs equals the table entry of the pair's bin, the lookup is reciprocal, and
// below the horizon it is 0.
TEST_F(MerlFiles, LookupAtRandomPairsIsReciprocal) {
  auto t = std::make_shared<MerlTable>(read_merl(path("ggx.binary")));
  MerlModel merl(t);
  std::mt19937 g(3);
  RowMatrix3d wi(500, 3), wr(500, 3);
  for (int r = 0; r < 500; ++r) {
    wi.row(r) = random_direction(g).transpose();
    wr.row(r) = random_direction(g).transpose();
  }
  Eigen::MatrixXd a(500, 3), b(500, 3);
  merl.eval(wi, wr, a);
  merl.eval(wr, wi, b);
  for (int r = 0; r < 500; ++r) {
    const MerlBin bin = merl_bin(wi.row(r).transpose(), wr.row(r).transpose());
    EXPECT_EQ(a(r, 1), t->at(1, bin));
    EXPECT_EQ(a(r, 0), b(r, 0));
  }
  RowMatrix3d below(1, 3), up(1, 3);
  below << 0.6, 0, -0.8;
  up << 0, 0, 1;
  Eigen::MatrixXd out(1, 3);
  merl.eval(below, up, out);
  EXPECT_EQ(out.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(merl.spec(), "merl:" + path("ggx.binary"));
}

// Minnaert k = 2 has the finite spectrum C = (k+1)/(2pi) c c^T on l = 0, n <= 2 (core/analytic_spectra),
// so fitting the table nodes with the isotropic modes of order 4 recovers it exactly (least squares of
// data in the span), per channel times 0.5, 0.7, 0.9.
TEST_F(MerlFiles, FitOfNodesRecoversAnalyticSpectrum) {
  const MerlTable t = read_merl(path("rgb.binary"));
  const MerlSamples s = merl_samples(t);
  EXPECT_EQ(s.missing, 0);
  EXPECT_EQ(s.wi.rows() + s.below_horizon, kMerlSamplesPerChannel);
  SampleFitOptions o;
  o.order = 4;
  o.isotropic = true;
  const SampleFitResult r = fit_samples(s.wi, s.wr, s.values, s.weights, o);
  EXPECT_EQ(r.effective_rank, r.unknowns);
  const Eigen::MatrixXd want = minnaert_coefficients(4, 2);
  for (int c = 0; c < 3; ++c)
    EXPECT_LT((r.channels[static_cast<size_t>(c)] - (0.5 + 0.2 * c) * want).cwiseAbs().maxCoeff(), kFitTol) << c;
  // The bin weights integrate the pair measure: their sum over all bins, valid or not, is
  // 4 * [integral sin theta_h over [0, pi/2]] * [integral cos sin theta_d over [0, pi/2]] * pi * 2pi * 2
  // = 4 * 1 * 1/2 * pi * 4 pi = 8 pi^2; the valid ones (both directions up) hold (2 pi)^2 = 4 pi^2 of it
  // up to the bins cut by the horizon, which are counted whole or not at all by their centre (they hold
  // ~1/90 of the measure and their errors largely cancel: 2e-3 leaves a margin of ~10 over what is seen).
  EXPECT_NEAR(s.weights.sum(), 4 * M_PI * M_PI, 2e-3 * 4 * M_PI * M_PI);
}

TEST_F(MerlFiles, MissingSamplesAreMaskedAndCounted) {
  ScratchDir d;
  // theta_d bins 40..42 missing for every theta_h, phi_d: 3 * 90 * 180 nodes, in all three channels.
  write_merl(d / "holes.binary", RgbMinnaert(), [](const MerlBin& b) { return b.theta_d >= 40 && b.theta_d <= 42; });
  const MerlTable t = read_merl(d / "holes.binary");
  for (int c = 0; c < 3; ++c) EXPECT_EQ(t.missing[static_cast<size_t>(c)], 3 * 90 * 180);
  EXPECT_TRUE(std::isnan(t.at(0, {10, 41, 5})));
  EXPECT_FALSE(std::isnan(t.at(0, {10, 43, 5})));
  Eigen::Vector3d wi, wr;
  directions_from_half_diff(merl_node({10, 41, 5}), wi, wr);
  MerlModel m(std::make_shared<MerlTable>(t));
  RowMatrix3d a(1, 3), b(1, 3);
  a.row(0) = wi.transpose();
  b.row(0) = wr.transpose();
  Eigen::MatrixXd out(1, 3);
  m.eval(a, b, out);
  EXPECT_TRUE(out.array().isNaN().all());
  // Fitting excludes them: the spectrum is still recovered from the remaining nodes.
  const MerlSamples s = merl_samples(t);
  EXPECT_GT(s.missing, 0);
  SampleFitOptions o;
  o.order = 4;
  o.isotropic = true;
  const SampleFitResult r = fit_samples(s.wi, s.wr, s.values, s.weights, o);
  EXPECT_LT((r.channels[0] - 0.5 * minnaert_coefficients(4, 2)).cwiseAbs().maxCoeff(), kFitTol);
}

// ---- bad input: every case gives an InputError whose one-line message names the file and the problem.

std::string message_of(const std::string& file) {
  return test::input_error_of(file, [&] { read_merl(file); });
}

void write_header(const std::string& file, std::int32_t a, std::int32_t b, std::int32_t c, std::int64_t extra_bytes = 0) {
  std::ofstream o(file, std::ios::binary);
  const std::int32_t d[3] = {a, b, c};
  o.write(reinterpret_cast<const char*>(d), 12);
  const std::string zeros(static_cast<size_t>(extra_bytes), '\0');
  o.write(zeros.data(), static_cast<std::streamsize>(zeros.size()));
}

std::int32_t bswap(std::int32_t v) {
  std::uint32_t u;
  std::memcpy(&u, &v, 4);
  u = (u >> 24) | ((u >> 8) & 0xff00u) | ((u << 8) & 0xff0000u) | (u << 24);
  std::memcpy(&v, &u, 4);
  return v;
}

TEST_F(MerlFiles, BadInputMessages) {
  ScratchDir d;
  const std::string good = path("rgb.binary");
  auto has = [](const std::string& m, const std::string& s) { EXPECT_NE(m.find(s), std::string::npos) << m << "\n  lacks: " << s; };

  test::write_bytes(d / "empty.binary", "");
  has(message_of(d / "empty.binary"), "empty file, expected a MERL file of 34992012 bytes");
  test::write_bytes(d / "short.binary", "abcde");
  has(message_of(d / "short.binary"), "truncated MERL header: 5 bytes, expected 12");

  // Truncated by one byte and one trailing byte: copies of the good file.
  const std::string bytes = test::read_bytes(good);
  ASSERT_EQ(static_cast<std::int64_t>(bytes.size()), kMerlFileBytes);
  test::write_bytes(d / "cut.binary", bytes.substr(0, bytes.size() - 1));
  has(message_of(d / "cut.binary"), "truncated MERL file: 34992011 bytes, expected 34992012 (1 bytes missing");
  test::write_bytes(d / "long.binary", bytes + "x");
  has(message_of(d / "long.binary"), "1 trailing bytes after the 3 x 90 x 90 x 180 doubles (file 34992013 bytes");

  write_header(d / "perm.binary", 180, 90, 90, kMerlFileBytes - 12);
  has(message_of(d / "perm.binary"), "MERL dims 180 x 90 x 90 are a permutation of the standard 90 x 90 x 180");
  write_header(d / "zero.binary", 90, 0, 180);
  has(message_of(d / "zero.binary"), "MERL dims must be positive, expected 90 x 90 x 180 (theta_h x theta_d x phi_d), found 90 x 0 x 180");
  write_header(d / "neg.binary", 90, 90, -180);
  has(message_of(d / "neg.binary"), "found 90 x 90 x -180");
  write_header(d / "huge.binary", 65536, 65536, 2);
  has(message_of(d / "huge.binary"), "MERL dims 65536 x 65536 x 2: sample count overflows int32 (max 2147483647)");
  write_header(d / "small.binary", 45, 45, 90);
  has(message_of(d / "small.binary"), "MERL dims expected 90 x 90 x 180 (theta_h x theta_d x phi_d), found 45 x 45 x 90");
  write_header(d / "swapped.binary", bswap(90), bswap(90), bswap(180), kMerlFileBytes - 12);
  has(message_of(d / "swapped.binary"), "byte-swapped MERL header");
  has(message_of(d / "swapped.binary"), "are 90 x 90 x 180 byte-swapped (a big-endian file)");

  // A NaN sample: overwrite the G value of bin (2, 3, 4).
  std::string nan_bytes = bytes;
  const double nan = std::nan("");
  std::memcpy(&nan_bytes[static_cast<size_t>(12 + 8 * (kMerlSamplesPerChannel + MerlBin{2, 3, 4}.flat()))], &nan, 8);
  test::write_bytes(d / "nan.binary", nan_bytes);
  has(message_of(d / "nan.binary"), "of channel G (theta_h bin 2, theta_d bin 3, phi_d bin 4) expected a finite number or -1, found NaN");

  write_merl(d / "gone.binary", RgbMinnaert(), [](const MerlBin&) { return true; });
  has(message_of(d / "gone.binary"), "all 4374000 MERL samples are missing (negative)");

  EXPECT_THROW(read_merl(d / "absent.binary"), InputError);
  EXPECT_THROW(read_merl(d.path()), InputError);  // a folder
}

}  // namespace
}  // namespace icobrdf
