// Analytic spectra: Lambert, ideal mirror and retroreflector (g form), Minnaert with integer exponent.
// Each closed form (icobrdf/core/spectrum/analytic_spectra.cpp, derivations there) is checked against an independent exact
// quadrature of its defining integral and against the values of SPEC-NOTES / docs/errata.md.
#include <gtest/gtest.h>

#include <cmath>

#include "icobrdf/core/spectrum/analytic_spectra.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "tests/core/hemisphere_quadrature.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using namespace icobrdf;

// Quadrature sums of O(1) products over a few thousand nodes: rounding only (the rules are exact).
constexpr double kQuadTol = 1e-13;
// Closed forms assembled from a handful of operations.
constexpr double kExactTol = 1e-14;

// integral h(w) K_j(w) dOmega for all j (one hemisphere, exact rule for degree `degree` in t, 2N+2 azimuths).
template <class H>
Eigen::VectorXd project(int order, int t_degree, H h) {
  const auto rule = test::hemisphere_rule(t_degree / 2 + 2, 2 * order + 2);
  const Eigen::MatrixXd k = hemisphere_basis_matrix(order, rule.dirs);
  Eigen::VectorXd w = rule.weights;
  for (Eigen::Index q = 0; q < w.size(); ++q) w[q] *= h(rule.dirs.row(q).transpose());
  return k.transpose() * w;
}

TEST(AnalyticSpectra, LambertUnitAlbedo) {
  // f = 1/pi is separable: C = (1/pi) p p^T with p_j = integral K_j dOmega (quadrature, exact at degree 0).
  const int order = 8;
  const Eigen::VectorXd p = project(order, order, [](const Eigen::Vector3d&) { return 1.0; });
  const Eigen::MatrixXd quad = p * p.transpose() / M_PI;
  const Eigen::MatrixXd c = lambert_coefficients(order);
  EXPECT_LE((c - quad).cwiseAbs().maxCoeff(), kQuadTol);
  // Only a_00^0, equal to 2 (= (1/pi) * (1/(2 pi)) * (2 pi)^2 with I_00^0 = 1/(2 pi) from Table 1); the
  // paper's (1/2) sqrt(2) is a misprint (docs/errata.md).
  const Eigen::VectorXd a = ibsss_from_coefficients(c);
  EXPECT_NEAR(a[0], 2.0, kExactTol);
  EXPECT_NEAR(a.tail(a.size() - 1).cwiseAbs().maxCoeff(), 0.0, kExactTol);
  EXPECT_NEAR(anisotropic_energy_fraction(c), 0.0, kExactTol);
  EXPECT_NEAR(lambert_coefficients(0, 0.3)(0, 0), 0.6, kExactTol);
}

TEST(AnalyticSpectra, IdealMirrorInGForm) {
  // g = delta(w_r - mirror(w_i)) (eq. 27): C_ab = integral K_a(w) K_b(mirror w) dOmega, by quadrature.
  const int order = 16;
  const auto rule = test::hemisphere_rule_for_order(order);
  RowMatrix3d mirrored = rule.dirs;
  mirrored.col(0) *= -1.0;
  mirrored.col(1) *= -1.0;
  const Eigen::MatrixXd k = hemisphere_basis_matrix(order, rule.dirs);
  const Eigen::MatrixXd km = hemisphere_basis_matrix(order, mirrored);
  const Eigen::MatrixXd quad = k.transpose() * rule.weights.asDiagonal() * km;
  const Eigen::MatrixXd c = mirror_g_coefficients(order);
  EXPECT_LE((c - quad).cwiseAbs().maxCoeff(), kQuadTol);
  // C = diag((-1)^l): flat BSSS with entries (-1)^l on the diagonal modes (not (-1)^k/pi as eq. 29 prints).
  const Eigen::VectorXd bsss = bsss_from_coefficients(c);
  for (int j = 0; j < c.rows(); ++j) {
    EXPECT_EQ(c(j, j), ansi_to_nl(j).l % 2 == 0 ? 1.0 : -1.0);
    EXPECT_EQ(bsss[helmholtz_mode_index(j, j)], c(j, j));
  }
  EXPECT_NEAR(bsss.cwiseAbs().sum(), c.rows(), kExactTol);  // nothing off the diagonal modes
  // IBSSS: a_nn^0 = 1, a_nn^l = sqrt(2) (-1)^l, all n != m vanish; isotropic.
  const Eigen::VectorXd a = ibsss_from_coefficients(c);
  const auto modes = isotropic_modes(order);
  for (size_t i = 0; i < modes.size(); ++i) {
    const auto [n, m, l] = modes[i];
    const double expect = n != m ? 0.0 : (l == 0 ? 1.0 : std::sqrt(2.0) * (l % 2 ? -1.0 : 1.0));
    EXPECT_NEAR(a[static_cast<Eigen::Index>(i)], expect, kExactTol) << n << m << l;
  }
  EXPECT_NEAR(anisotropic_energy_fraction(c), 0.0, kExactTol);
}

TEST(AnalyticSpectra, IdealRetroreflectorInGForm) {
  // g = delta(w_r - w_i) (eq. 31): C_ab = integral K_a K_b dOmega = delta_ab, by quadrature.
  const int order = 16;
  const auto rule = test::hemisphere_rule_for_order(order);
  const Eigen::MatrixXd k = hemisphere_basis_matrix(order, rule.dirs);
  const Eigen::MatrixXd quad = k.transpose() * rule.weights.asDiagonal() * k;
  const Eigen::MatrixXd c = retroreflector_g_coefficients(order);
  EXPECT_LE((c - quad).cwiseAbs().maxCoeff(), kQuadTol);
  // IBSSS: a_nn^0 = 1, a_nn^l = sqrt(2), n != m vanish (eq. 34 prints (1/pi) delta delta).
  const Eigen::VectorXd a = ibsss_from_coefficients(c);
  const auto modes = isotropic_modes(order);
  for (size_t i = 0; i < modes.size(); ++i) {
    const auto [n, m, l] = modes[i];
    const double expect = n != m ? 0.0 : (l == 0 ? 1.0 : std::sqrt(2.0));
    EXPECT_NEAR(a[static_cast<Eigen::Index>(i)], expect, kExactTol) << n << m << l;
  }
  EXPECT_NEAR(anisotropic_energy_fraction(c), 0.0, kExactTol);
}

TEST(AnalyticSpectra, MinnaertIntegerExponentIsFinite) {
  // f = (k+1)/(2 pi) (cos theta_i cos theta_r)^(k-1): separable, C = (k+1)/(2 pi) p p^T with
  // p_j = integral cos^(k-1) K_j dOmega by quadrature (cos theta = 1 - t: degree k-1 + N/2 in t).
  for (int k = 1; k <= 6; ++k) {
    const int q = k - 1, order = 2 * q + 6;  // six orders past the last nonzero one
    const Eigen::VectorXd p =
        project(order, q + order, [q](const Eigen::Vector3d& d) { return std::pow(d.z(), q); });
    const Eigen::MatrixXd quad = (k + 1) / (2 * M_PI) * p * p.transpose();
    const Eigen::MatrixXd c = minnaert_coefficients(order, k);
    const double scale = quad.cwiseAbs().maxCoeff();
    EXPECT_LE((c - quad).cwiseAbs().maxCoeff(), kQuadTol * std::max(scale, 1.0)) << "k = " << k;
    // Tail: every coefficient with n > 2(k-1) or l != 0 is exactly zero; n = 2(k-1), l = 0 is not.
    for (int a = 0; a < c.rows(); ++a)
      for (int b = 0; b < c.rows(); ++b) {
        const auto ka = ansi_to_nl(a), kb = ansi_to_nl(b);
        if (ka.n > 2 * q || kb.n > 2 * q || ka.l != 0 || kb.l != 0 || ka.n % 2 || kb.n % 2) {
          EXPECT_EQ(c(a, b), 0.0) << "k = " << k << " a = " << a << " b = " << b;
        }
      }
    const int last = ansi_index(2 * q, 0);
    EXPECT_GT(std::abs(c(last, last)), 1e-6) << "k = " << k;
    EXPECT_NEAR(anisotropic_energy_fraction(c), 0.0, kExactTol);
  }
  // k = 1 is unit-albedo Lambert.
  EXPECT_LE((minnaert_coefficients(6, 1) - lambert_coefficients(6)).cwiseAbs().maxCoeff(), kExactTol);
  // k = 2: f = (3/(2 pi)) cos_i cos_r; cos = 1 - t = (1 - P_1(2t-1))/2 gives
  // p_0 = sqrt(2 pi) / 2 and p_{2,0} = sqrt(6 pi) * (-1/6): hand values of the moment formula.
  const Eigen::VectorXd p2 = cosine_power_projection(2, 1);
  EXPECT_NEAR(p2[0], std::sqrt(2 * M_PI) / 2, kExactTol);
  EXPECT_NEAR(p2[ansi_index(2, 0)], -std::sqrt(6 * M_PI) / 6, kExactTol);
}

TEST(AnalyticSpectra, RejectsBadArguments) {
  EXPECT_THROW(minnaert_coefficients(4, 0), ArgumentError);
  EXPECT_THROW(minnaert_coefficients(-1, 2), ArgumentError);
  EXPECT_THROW(mirror_g_coefficients(129), ArgumentError);
  EXPECT_THROW(cosine_power_projection(4, -1), ArgumentError);
}

}  // namespace ICOBRDF_UNITY_ID
