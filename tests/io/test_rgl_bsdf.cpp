// RGL materials (icobrdf/io/rgl_bsdf.hpp) and the FILE.bsdf SOURCE (icobrdf/io/measured_sources.hpp). The files are written
// here (tests/io/rgl_test_files.hpp) with tables whose values are known at every node, and the expected f
// is derived by hand from the format's definition:
//   - Lambertian data: the stored value at a node is rho/pi cos(theta_o) for the direction pair that node
//     stands for (w_o = the reflection of w_i about the node's microfacet normal), so f = rho/pi there;
//   - a vndf linear in u_theta (a + b x) warps u to (a u + b u^2 / 2) / (a + b / 2), and value tables
//     affine in the sample are interpolated exactly, so f is known in closed form at any direction pair;
//   - slices are blended linearly in theta_i / phi_i / wavelength and held beyond the end nodes.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/rgl_bsdf.hpp"
#include "io_test_support.hpp"
#include "rgl_test_files.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::RglFileSpec;
using test::ScratchDir;

// Values stored as float32: relative rounding 2^-24 of the value, about 6e-8, amplified a little by
// the interpolation weights; 1e-6 covers it with margin.
constexpr double kFloatTol = 1e-6;
// Tables whose values are exact in float32: what remains is double rounding of the direction arithmetic
// (acos/atan2 of the half vector, a few sqrt), a few 1e-16 relative, amplified by 1/cos(theta_o) <= 10.
constexpr double kExactTol = 1e-11;

Eigen::Vector3d dir(double theta, double phi) { return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)}; }
Eigen::Vector3d reflect(const Eigen::Vector3d& wi, const Eigen::Vector3d& m) { return 2 * wi.dot(m) * m - wi; }

Eigen::MatrixXd eval_pairs(const BrdfSource& s, const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& pairs) {
  RowMatrix3d wi(pairs.size(), 3), wr(pairs.size(), 3);
  for (size_t k = 0; k < pairs.size(); ++k) wi.row(k) = pairs[k].first.transpose(), wr.row(k) = pairs[k].second.transpose();
  return s.eval(wi, wr);
}

std::string write(const ScratchDir& d, const std::string& name, const RglFileSpec& spec) {
  write_tensor_file(d / name, test::rgl_fields(spec));
  return d / name;
}

// The direction pair of node (k, j) of an isotropic file's slice theta_i (phi_i = 0): theta_m =
// (pi/2) (k/(w-1))^2, phi_m = (2 j/(h-1) - 1) pi.
std::pair<Eigen::Vector3d, Eigen::Vector3d> node_pair(double theta_i, int k, int j, int w, int h) {
  const double u = k / (w - 1.0), tm = M_PI / 2 * u * u, pm = (2.0 * j / (h - 1) - 1) * M_PI;
  const Eigen::Vector3d wi = dir(theta_i, 0.0);
  return {wi, reflect(wi, dir(tm, pm))};
}

TEST(RglBsdf, LambertianDataEvaluateToRhoOverPi) {
  ScratchDir d;
  for (bool jacobian : {false, true}) {
    RglFileSpec s;
    s.theta = {0.0, 0.25, 0.5, 1.0};
    s.w = 9;
    s.h = 9;
    s.jacobian = jacobian;
    s.ndf = 2.0;
    s.sigma = 0.25;  // D / (4 sigma) = 2: stored values are divided by it
    const double rho[3] = {0.2, 0.5, 0.8};
    s.value = [&](int, int t, int c, int k, int j) {
      const auto [wi, wo] = node_pair(s.theta[t], k, j, s.w, s.h);
      return rho[c] / M_PI * std::max(wo.z(), 0.0) / (jacobian ? 2.0 : 1.0);
    };
    const auto src = open_source(write(d, "lambert.bsdf", s));
    EXPECT_EQ(src->channels(), 3);
    EXPECT_EQ(src->channel_names(), (std::vector<std::string>{"r", "g", "b"}));
    std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
    for (double t : s.theta)
      for (int k = 0; k < s.w; ++k)
        for (int j = 0; j < s.h; ++j) {
          const auto p = node_pair(t, k, j, s.w, s.h);
          if (p.second.z() > 0.1) pairs.push_back(p);
        }
    ASSERT_GT(pairs.size(), 100u);
    const Eigen::MatrixXd f = eval_pairs(*src, pairs);
    for (Eigen::Index r = 0; r < f.rows(); ++r)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(f(r, c), rho[c] / M_PI, kFloatTol * rho[c] / M_PI) << "pair " << r << " jacobian " << jacobian;
  }
}

double linear_cdf(double x, double a, double b) { return (a * x + b * x * x / 2) / (a + b / 2); }

// u coordinates of the half vector of a pair, computed with acos (the reader uses 2 asin(|w - z| / 2)).
void half_vector_u(const Eigen::Vector3d& wi, const Eigen::Vector3d& wo, bool relative, double& ux, double& uy) {
  const Eigen::Vector3d m = (wi + wo).normalized();
  ux = std::sqrt(std::acos(m.z()) * 2 / M_PI);
  const double phi = std::atan2(m.y(), m.x()) - (relative ? std::atan2(wi.y(), wi.x()) : 0.0);
  uy = (phi + M_PI) / (2 * M_PI);
  uy -= std::floor(uy);
}

TEST(RglBsdf, LinearVndfWarpsToItsCdfAtAnyDirections) {
  ScratchDir d;
  RglFileSpec s;
  s.theta = {0.5};
  const double a = 0.5, b = 2.0;  // vndf a + b x: exact in float32 at x = k / 4
  s.vndf = [&](int, int, int k, int) { return a + b * k / 4.0; };
  // Channel c: 0.25 + (c + 1) s_x + 0.5 s_y, exact at the nodes.
  s.value = [](int, int, int c, int k, int j) { return 0.25 + (c + 1) * k / 4.0 + 0.5 * j / 4.0; };
  const auto src = open_source(write(d, "linear.bsdf", s));
  std::mt19937 g(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>> pairs;
  while (pairs.size() < 200) {
    const Eigen::Vector3d wi = dir(0.5, 2 * M_PI * u(g)), wo = dir(std::acos(0.1 + 0.9 * u(g)), 2 * M_PI * u(g));
    double ux, uy;
    half_vector_u(wi, wo, true, ux, uy);
    if (uy > 1e-6 && uy < 1 - 1e-6) pairs.emplace_back(wi, wo);  // away from the azimuth seam
  }
  const Eigen::MatrixXd f = eval_pairs(*src, pairs);
  for (size_t r = 0; r < pairs.size(); ++r) {
    double ux, uy;
    half_vector_u(pairs[r].first, pairs[r].second, true, ux, uy);
    const double sx = linear_cdf(ux, a, b);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(f(r, c), (0.25 + (c + 1) * sx + 0.5 * uy) / pairs[r].second.z(), kExactTol * 10) << r;
  }
}

TEST(RglBsdf, ThetaSlicesBlendWarpAndValuesAndHoldAtTheEnds) {
  ScratchDir d;
  RglFileSpec s;
  s.theta = {0.25, 0.75};
  const double a = 1.0, b = 3.0;
  s.vndf = [&](int, int t, int k, int) { return t == 0 ? a + b * k / 4.0 : 5.0; };  // slice 1 constant: identity
  s.value = [](int, int t, int, int k, int) { return (t == 0 ? 1.0 : 3.0) + 2.0 * k / 4.0; };
  const auto src = open_source(write(d, "blend.bsdf", s));
  const Eigen::Vector3d wo = dir(0.6, 2.0);
  for (const auto& [theta, w1] : std::vector<std::pair<double, double>>{{0.5, 0.5}, {0.25, 0.0}, {0.1, 0.0}, {0.75, 1.0}, {1.3, 1.0}, {0.375, 0.25}}) {
    const Eigen::Vector3d wi = dir(theta, 0.3);
    double ux, uy;
    half_vector_u(wi, wo, true, ux, uy);
    const double sx = (1 - w1) * linear_cdf(ux, a, b) + w1 * ux;
    const double expected = ((1 - w1) * 1.0 + w1 * 3.0 + 2.0 * sx) / wo.z();
    EXPECT_NEAR(eval_pairs(*src, {{wi, wo}})(0, 0), expected, kExactTol * expected) << theta;
  }
}

TEST(RglBsdf, IlluminationDirectionSelectsTheSlice) {
  // Slice values 1 (theta_i = 0.25) and 4 (theta_i = 0.75), constant: swapping the directions of a pair
  // swaps the slice, so f(w_i, w_r) = 1 / cos(theta_r) and f(w_r, w_i) = 4 / cos(theta_i).
  ScratchDir d;
  RglFileSpec s;
  s.theta = {0.25, 0.75};
  s.value = [](int, int t, int, int, int) { return t == 0 ? 1.0 : 4.0; };
  const auto src = open_source(write(d, "slices.bsdf", s));
  const Eigen::Vector3d a = dir(0.25, 0.4), b = dir(0.75, 2.2);
  EXPECT_NEAR(eval_pairs(*src, {{a, b}})(0, 1), 1.0 / b.z(), kExactTol);
  EXPECT_NEAR(eval_pairs(*src, {{b, a}})(0, 1), 4.0 / a.z(), kExactTol);
  // Below the horizon: 0, as Mitsuba.
  EXPECT_EQ(eval_pairs(*src, {{a, Eigen::Vector3d(0.6, 0, -0.8)}})(0, 0), 0.0);
  EXPECT_EQ(eval_pairs(*src, {{Eigen::Vector3d(1, 0, 0), b}})(0, 0), 0.0);
}

TEST(RglBsdf, AzimuthReductionsMapTheIncidentAzimuth) {
  ScratchDir d;
  // Reduction 2 (phi_i spans pi): w_i with y >= 0 is rotated by pi. Slice values 1, 2, 3 at phi -pi, -pi/2, 0.
  RglFileSpec s;
  s.phi = {-M_PI, -M_PI / 2, 0.0};
  s.theta = {0.5};
  s.value = [](int p, int, int, int, int) { return 1.0 + p; };
  const auto two = open_source(write(d, "two.bsdf", s));
  const Eigen::Vector3d wo = dir(0.4, 1.0);
  const auto f = [&](const BrdfSource& src, double phi) { return eval_pairs(src, {{dir(0.5, phi), wo}})(0, 0) * wo.z(); };
  EXPECT_NEAR(f(*two, -M_PI / 2), 2.0, kFloatTol);
  EXPECT_NEAR(f(*two, M_PI / 2), 2.0, kFloatTol);      // rotated to -pi/2
  EXPECT_NEAR(f(*two, -M_PI / 4), 2.5, kFloatTol);     // halfway between -pi/2 and 0
  EXPECT_NEAR(f(*two, 3 * M_PI / 4), 2.5, kFloatTol);  // rotated to -pi/4
  // Reduction 4 (phi_i spans pi/2, nodes -pi, -3pi/4, -pi/2): x and y negated separately when >= 0.
  s.phi = {-M_PI, -3 * M_PI / 4, -M_PI / 2};
  const auto four = open_source(write(d, "four.bsdf", s));
  EXPECT_NEAR(f(*four, -3 * M_PI / 4), 2.0, kFloatTol);
  EXPECT_NEAR(f(*four, M_PI / 4), 2.0, kFloatTol);      // (+, +) -> (-, -)
  EXPECT_NEAR(f(*four, 3 * M_PI / 4), 2.0, kFloatTol);  // (-, +) -> (-, -)
  EXPECT_NEAR(f(*four, -M_PI / 4), 2.0, kFloatTol);     // (+, -) -> (-, -)
  EXPECT_NEAR(f(*four, -7 * M_PI / 8), 1.5, kFloatTol);
}

TEST(RglBsdf, SpectralChannelsAreWavelengthsAndInterpolate) {
  ScratchDir d;
  RglFileSpec s;
  s.theta = {0.5};
  s.wavelengths = {400, 500, 600};
  s.value = [](int, int, int c, int, int) { return c == 0 ? 1.0 : c == 1 ? 2.0 : 4.0; };
  const std::string path = write(d, "spec.bsdf", s);
  const Eigen::Vector3d wi = dir(0.5, 0.0), wo = dir(0.3, 3.0);
  const auto all = open_source(path);
  EXPECT_EQ(all->channel_names(), (std::vector<std::string>{"400nm", "500nm", "600nm"}));
  const Eigen::MatrixXd v = eval_pairs(*all, {{wi, wo}}) * wo.z();
  EXPECT_NEAR(v(0, 0), 1.0, kExactTol);
  EXPECT_NEAR(v(0, 2), 4.0, kExactTol);
  const auto one = open_source(path + "#lambda=450");
  EXPECT_NEAR(eval_pairs(*one, {{wi, wo}})(0, 0) * wo.z(), 1.5, kExactTol);
  const auto two = open_source("rgl:" + path + "#lambda=550/600");
  EXPECT_EQ(two->channel_names(), (std::vector<std::string>{"550nm", "600nm"}));
  EXPECT_NEAR(eval_pairs(*two, {{wi, wo}})(0, 0) * wo.z(), 3.0, kExactTol);
  EXPECT_THROW(open_source(path + "#lambda=300"), ArgumentError);
  EXPECT_THROW(open_source(path + "#lambda=400/500/600/500"), ArgumentError);
  EXPECT_THROW(open_source(path + "#gamma=2"), ArgumentError);
  // A fit needs 1 or 3 channels: 3 wavelengths are fine, but an RGB file refuses lambda.
  RglFileSpec rgb;
  EXPECT_THROW(open_source(write(d, "rgb.bsdf", rgb) + "#lambda=500"), ArgumentError);
}

// ---- malformed files: one-line InputError naming the file and the field.

std::string message_of(const std::string& file) {
  return test::input_error_of(file, [&] { read_rgl_bsdf(file); });
}

TEST(RglBsdf, MalformedFilesGiveOneLineErrors) {
  ScratchDir d;
  const std::string f = d / "bad.bsdf";
  RglFileSpec base;
  base.theta = {0.0, 0.5};
  const auto check = [&](const std::vector<TensorField>& fields, const std::string& expected) {
    write_tensor_file(f, fields);
    const std::string m = message_of(f);
    EXPECT_NE(m.find(expected), std::string::npos) << m;
  };
  const auto without = [&](const std::string& name) {
    auto v = test::rgl_fields(base);
    v.erase(std::remove_if(v.begin(), v.end(), [&](const TensorField& x) { return x.name == name; }), v.end());
    return v;
  };
  const auto replaced = [&](const TensorField& nf) {
    auto v = test::rgl_fields(base);
    for (auto& x : v)
      if (x.name == nf.name) x = nf;
    return v;
  };
  check(without("vndf"), "missing field 'vndf' (expected float32, 4-D)");
  check(without("jacobian"), "missing field 'jacobian'");
  TensorField t64 = float32_field("theta_i", {2}, {0.0, 0.5});
  t64.dtype = TensorDtype::Float64;
  t64.bytes.resize(16);
  check(replaced(t64), "field 'theta_i': expected float32, found float64");
  check(replaced(float32_field("theta_i", {2}, {0.5, 0.5})), "field 'theta_i': expected strictly increasing nodes");
  check(replaced(float32_field("theta_i", {3}, {0.0, 0.5, 1.0})), "field 'vndf': shape [1, 2, 5, 5]: dimension 1 expected 3 (|theta_i|), found 2");
  check(replaced(float32_field("luminance", {1, 2, 5, 4}, std::vector<double>(40, 1.0))), "field 'luminance': shape [1, 2, 5, 4]: dimension 3 expected 5 (square sample grid)");
  check(replaced(float32_field("rgb", {1, 2, 4, 5, 5}, std::vector<double>(200, 1.0))), "field 'rgb': shape [1, 2, 4, 5, 5]: dimension 2 expected 3 (R, G, B)");
  check(replaced(uint8_field("jacobian", {1}, {2})), "field 'jacobian': expected 0 or 1, found 2");
  check(replaced(float32_field("ndf", {1, 2}, {1.0, 1.0})), "field 'ndf': shape [1, 2]: expected a table of 2 .. 1048576 nodes");
  std::vector<double> vndf(50, 1.0);
  vndf[7] = -1;
  check(replaced(float32_field("vndf", {1, 2, 5, 5}, vndf)), "field 'vndf': value 7: expected a finite number >= 0, found -1");
  std::fill(vndf.begin(), vndf.end(), 1.0);
  std::fill(vndf.begin() + 25, vndf.end(), 0.0);
  check(replaced(float32_field("vndf", {1, 2, 5, 5}, vndf)), "field 'vndf': density table: slice 1 integrates to 0");
  std::vector<double> rgb(150, 1.0);
  rgb[99] = NAN;
  check(replaced(float32_field("rgb", {1, 2, 3, 5, 5}, rgb)), "field 'rgb': value 99: expected a finite number, found nan");
  base.jacobian = true;
  base.sigma = 0.0;
  check(test::rgl_fields(base), "field 'sigma': value 0: expected > 0 (jacobian is 1, sigma divides)");
  base = RglFileSpec();
  base.phi = {0.0, 1.0, 2.0};
  check(test::rgl_fields(base), "field 'phi_i': nodes span 2.000000 rad, expected 2 pi, pi or pi/2");
  EXPECT_NE(message_of(d / "absent.bsdf").find("no such tensor file"), std::string::npos);
}

TEST(RglBsdf, SourceErrorsAreOneLine) {
  ScratchDir d;
  try {
    open_source(d / "absent.bsdf");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no such file"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace icobrdf
