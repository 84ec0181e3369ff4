// icobrdf/pipeline/reflectance_check.hpp: non-finite values refused whatever the flags; negative reflectance beyond
// rounding reported as non-physical (one warning line by default, InputError under strict); the LUT and
// fitted-spectrum forms on a negated Lambertian, whose directional albedo is derived below (-albedo).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "icobrdf/core/spectrum/analytic_spectra.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/projection/reflection.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/pipeline/reflectance_check.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using namespace icobrdf;

int lines(const std::string& s) { return static_cast<int>(std::count(s.begin(), s.end(), '\n')); }

TEST(ReflectanceCheck, RoundingPassesNegativeWarnsStrictRefusesInfAlwaysRefused) {
  std::ostringstream warn;
  const ReflectanceCheck lax{false, &warn}, strict{true, &warn};
  Eigen::MatrixXd v = Eigen::MatrixXd::Constant(4, 2, 0.3);
  // Within the rounding tolerance of the largest magnitude: silent in both modes.
  v(1, 1) = -0.5 * kNegativeReflectanceTolerance * 0.3;
  EXPECT_NO_THROW(check_reflectance(v, "src", "step", "f", strict));
  EXPECT_EQ(warn.str(), "");
  // Beyond it: one warning naming where, step, quantity, value and place; an InputError under strict.
  v(1, 1) = -2.0 * kNegativeReflectanceTolerance * 0.3;
  check_reflectance(v, "src", "step", "f", lax);
  EXPECT_EQ(lines(warn.str()), 1);
  EXPECT_EQ(warn.str().rfind("icobrdf: warning: src: step gave a negative f of ", 0), 0u) << warn.str();
  EXPECT_NE(warn.str().find("at [1, 1]"), std::string::npos) << warn.str();
  EXPECT_NE(warn.str().find("non-physical"), std::string::npos) << warn.str();
  EXPECT_THROW(check_reflectance(v, "src", "step", "f", strict), InputError);
  // Overflow: refused even without strict, before any sign test.
  v(2, 0) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(check_reflectance(v, "src", "step", "f", lax), UnsupportedError);
  v(2, 0) = std::nan("");
  EXPECT_THROW(check_reflectance(v, "src", "step", "f", lax), UnsupportedError);
}

// f = -albedo/pi sampled on the equal-area grid: the directional albedo is -albedo at every cell (the cells'
// mean cosines times solid angles sum to the integral of cos over the hemisphere, pi, up to the cubature).
TEST(ReflectanceCheck, NegatedLambertLutAndSpectrumAreNonPhysical) {
  const Grid grid = build_equal_area_grid(2);
  const double albedo = 0.5;
  Eigen::MatrixXd lut = Eigen::MatrixXd::Constant(grid.cells(), grid.cells(), albedo / M_PI);
  const Eigen::VectorXd a = directional_albedo(lut, false, grid);
  EXPECT_NEAR(a.minCoeff(), albedo, 1e-8);  // the cells' cubature of cos at level 2: within 4e-9
  std::ostringstream warn;
  check_lut({lut}, false, grid, "pos.h5", {true, &warn});  // the positive LUT passes even strict
  EXPECT_EQ(warn.str(), "");
  lut = -lut;
  check_lut({lut}, false, grid, "neg.h5", {false, &warn});
  EXPECT_EQ(lines(warn.str()), 2) << warn.str();  // the LUT entries, then the albedo
  EXPECT_NE(warn.str().find("negative directional albedo of -0.5 "), std::string::npos) << warn.str();
  EXPECT_THROW(check_lut({lut}, false, grid, "neg.h5", {true, &warn}), InputError);

  Spectrum s;
  s.order = 2;
  s.channels = {lambert_coefficients(2, -albedo)};
  std::ostringstream w2;
  check_fitted_albedo(s, grid, "fit x", {false, &w2});
  EXPECT_NE(w2.str().find("negative directional albedo of -0.5"), std::string::npos) << w2.str();
  EXPECT_THROW(check_fitted_albedo(s, grid, "fit x", {true, &w2}), InputError);
  s.channels = {lambert_coefficients(2, albedo)};
  EXPECT_NO_THROW(check_fitted_albedo(s, grid, "fit x", {true, &w2}));
}

}  // namespace
