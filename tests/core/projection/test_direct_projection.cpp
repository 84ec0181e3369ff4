// Direct quadrature without matrices (icobrdf/core/projection/direct_projection.hpp) against closed-form spectra and the matrix
// path. Grids: the polar-Gauss product rule (one point per cell), whose exactness degrees are known.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include "icobrdf/core/spectrum/analytic_spectra.hpp"
#include "icobrdf/core/projection/direct_projection.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/grid/reference_grids.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {

// Sums of a few thousand products of terms bounded by ~10 (|K| <= sqrt((n+1)/pi), f <= 1): 1e-12 absolute.
constexpr double kQuadratureRoundingTol = 1e-12;
// Same sums in a different order, relative to the largest coefficient.
constexpr double kSameSumRelTol = 1e-12;

double max_abs(const Eigen::MatrixXd& a) { return a.cwiseAbs().maxCoeff(); }

TEST(DirectProjection, LambertIsExactOnAnExactProductRule) {
  // f = 1/pi: C_ab = (1/pi) (integral K_a)(integral K_b); integral K_a dOmega is a polynomial of degree <= N/2
  // in t times a trigonometric polynomial of degree <= N, integrated exactly by rings >= (N + 1)/2,
  // n_phi >= N + 1. Closed form: C_00 = 2, all else 0 (lambert_coefficients, docs/errata.md 1).
  const int order = 6;
  const Grid g = build_polar_gauss_grid(4, 14);
  const auto model = parse_model("lambert");
  for (const auto modes : {DirectModes::PerPair, DirectModes::Cached}) {
    const auto c = direct_projection(*model, g, order, false, modes);
    ASSERT_EQ(c.size(), 1u);
    EXPECT_LT(max_abs(c[0] - lambert_coefficients(order)), kQuadratureRoundingTol);
  }
}

TEST(DirectProjection, MinnaertIsExactOnAnExactProductRule) {
  // Minnaert k = 3: f = (2/pi) (1 - t_i)^2 (1 - t_r)^2; per variable the integrand (1 - t)^2 K_a is of degree
  // <= 2 + N/2 = 6 in t for N = 8, exact with 4 Gauss rings (degree 7); n_phi = 9 covers trig degree 8.
  const int order = 8;
  const Grid g = build_polar_gauss_grid(4, 9);
  const auto model = parse_model("minnaert:k=3");
  const auto c = direct_projection(*model, g, order, false, DirectModes::Cached);
  EXPECT_LT(max_abs(c[0] - minnaert_coefficients(order, 3)), kQuadratureRoundingTol);
}

TEST(DirectProjection, PerPairAndCachedModesAgreeToRounding) {
  const Grid g = build_polar_gauss_grid(5, 12);
  const auto model = parse_model("ggx:alpha=0.3");
  const auto a = direct_projection(*model, g, 6, true, DirectModes::PerPair);
  const auto b = direct_projection(*model, g, 6, true, DirectModes::Cached);
  EXPECT_LT(max_abs(a[0] - b[0]) / max_abs(a[0]), kSameSumRelTol);
}

TEST(DirectProjection, AgreesWithTheMatrixPathOnOnePointCells) {
  // One point per cell: B_ca = K_a(x_c), F_ir = f(x_i, x_r), so P = W B gives P^T F P = the direct sum, and
  // P = W B G^-1 gives G^-1 (direct) G^-1 (icobrdf/core/projection/direct_projection.hpp).
  const int order = 6;
  const Grid g = build_polar_gauss_grid(5, 12);  // order 6 needs rings >= 3.5 and n_phi >= 13 for G = I: not met
  const auto model = parse_model("ggx:alpha=0.3");
  const auto basis = build_discrete_basis(g, order);
  const Lut lut = build_lut(*model, g, false, LutSampling::CellAverage);
  const auto direct = direct_projection(*model, g, order, false, DirectModes::PerPair);
  const double scale = max_abs(direct[0]);
  const auto plain = project_lut(make_projection(basis, ProjectionOperator::Kind::Plain), lut.channels[0]);
  EXPECT_LT(max_abs(plain - direct[0]) / scale, kSameSumRelTol);
  const Eigen::MatrixXd gi = basis.G.inverse();
  const auto ls = project_lut(make_projection(basis), lut.channels[0]);
  EXPECT_LT(max_abs(ls - gi * direct[0] * gi) / max_abs(ls), kSameSumRelTol * basis.condition);
}

TEST(DirectProjection, RefusesDeltaModels) {
  const Grid g = build_polar_gauss_grid(3, 8);
  EXPECT_THROW(direct_projection(*parse_model("mirror"), g, 2, true), ArgumentError);
}

}  // namespace ICOBRDF_UNITY_ID
