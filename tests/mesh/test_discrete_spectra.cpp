// Discrete spectra on the equal-area tessellation against the analytic spectra (icobrdf/core/spectrum/analytic_spectra.hpp),
// for levels 3-6. Each expected value or bound is derived in a comment.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>

#include "icobrdf/core/spectrum/analytic_spectra.hpp"
#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "tests/support/unity_id.hpp"

using namespace icobrdf;

namespace ICOBRDF_UNITY_ID {

// Linear algebra on matrices of up to a few hundred modes and 40k cells: 1e-10 covers the rounding of G^-1.
constexpr double kAlgebraTol = 1e-10;

// Minnaert with k = 3: f = (k+1)/(2 pi) (cos_i cos_r)^(k-1) = (2/pi) (cos_i cos_r)^2.
struct Minnaert3 final : BrdfModel {
  using BrdfModel::eval;
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override {
    out.col(0) = (2.0 / M_PI) * (wi.col(2).array() * wr.col(2).array()).square().matrix();
  }
  std::string spec() const override { return "minnaert:k=3"; }
};
struct Constant final : BrdfModel {
  using BrdfModel::eval;
  void eval(const RowMatrix3d&, const RowMatrix3d&, Eigen::Ref<Eigen::MatrixXd> out) const override { out.setConstant(1.0 / M_PI); }
  std::string spec() const override { return "lambert"; }
};

// Spectral norm of G - I: with G = I + E, ||G^-1 - I||_2 <= ||E||_2 / (1 - ||E||_2), a bound on every entry.
double inverse_deviation_bound(const Eigen::MatrixXd& g) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(g - Eigen::MatrixXd::Identity(g.rows(), g.cols()), Eigen::EigenvaluesOnly);
  const double e = eig.eigenvalues().cwiseAbs().maxCoeff();
  return e / (1.0 - e);
}

struct LevelOrder {
  int level, order;
};
// Orders up to what each level supports at the default Gram tolerance (3: 6, 4: 11, 5: 20, 6: 32), capped
// at 16 on level 6 to keep the test within seconds.
const LevelOrder kCases[] = {{3, 6}, {4, 11}, {5, 20}, {6, 16}};

TEST(DiscreteSpectra, MirrorAndRetroreflectorMatchTheAnalyticSpectraWithinTheGramError) {
  // Mirror: C = D G^-1 exactly (tests/core/projection/test_operators.cpp), so C G = D, and
  // |C - D|_max <= |G^-1 - I|_2 <= ||G - I||_2 / (1 - ||G - I||_2). Retroreflector: C = G^-1, same bound.
  for (const auto [level, order] : kCases) {
    const Grid g = build_equal_area_grid(level);
    const auto b = build_discrete_basis(g, order);
    ASSERT_NO_THROW(check_supported(b)) << "level " << level << " order " << order;
    const auto p = make_projection(b);
    const Eigen::MatrixXd mirror = delta_projection({DeltaPart::Mirror, 1.0}, g, p);
    const Eigen::MatrixXd retro = delta_projection({DeltaPart::Retroreflector, 1.0}, g, p);
    const Eigen::MatrixXd d = mirror_g_coefficients(order), id = retroreflector_g_coefficients(order);
    EXPECT_LT((mirror * b.G - d).cwiseAbs().maxCoeff(), kAlgebraTol) << "level " << level;
    EXPECT_LT((retro * b.G - id).cwiseAbs().maxCoeff(), kAlgebraTol) << "level " << level;
    const double bound = inverse_deviation_bound(b.G);
    EXPECT_LE((mirror - d).cwiseAbs().maxCoeff(), bound) << "level " << level;
    EXPECT_LE((retro - id).cwiseAbs().maxCoeff(), bound) << "level " << level;
  }
}

TEST(DiscreteSpectra, MirrorErrorShrinksFourfoldPerLevel) {
  // Cell averaging attenuates K_n^l by 1 - O((n h)^2) with h ~ 2^-L the cell size, so the Gram error and
  // the mirror spectrum's error fall by ~4 per level at fixed order: accept a ratio in [3, 5].
  const int order = 6;
  double previous = 0.0;
  for (int level = 3; level <= 6; ++level) {
    const Grid g = build_equal_area_grid(level);
    const auto b = build_discrete_basis(g, order);
    const auto p = make_projection(b);
    const double err = (delta_projection({DeltaPart::Mirror, 1.0}, g, p) - mirror_g_coefficients(order)).cwiseAbs().maxCoeff();
    if (level > 3) {
      const double ratio = previous / err;
      EXPECT_GT(ratio, 3.0) << "level " << level;
      EXPECT_LT(ratio, 5.0) << "level " << level;
    }
    previous = err;
  }
}

TEST(DiscreteSpectra, LambertAndMinnaertAreExactOnTheGrid) {
  // f in the span of K up to the order (Lambert: order 0, Minnaert k = 3: order 4) gives the cell-averaged
  // LUT B C B^T exactly (separable cell averages with the same cubature as B), so P^T F P = C on any grid,
  // independently of its Gram error. Streaming projection with the grid's own cubature (degree 2 here,
  // so the test stays fast; B uses the same rule).
  for (int level : {3, 4}) {
    const Grid g = build_equal_area_grid(level, 2);
    const auto b = build_discrete_basis(g, 6);
    const auto p = make_projection(b);
    const auto lambert = streaming_projection(Constant(), g, p, false);
    EXPECT_LT((lambert[0] - lambert_coefficients(6)).cwiseAbs().maxCoeff(), kAlgebraTol) << "level " << level;
    const auto minnaert = streaming_projection(Minnaert3(), g, p, false);
    EXPECT_LT((minnaert[0] - minnaert_coefficients(6, 3)).cwiseAbs().maxCoeff(), kAlgebraTol) << "level " << level;
  }
}

}  // namespace ICOBRDF_UNITY_ID
