// Antisymmetric modes Z_ab and J_nm^l (icobrdf/core/basis/antisymmetric_modes.hpp): C <-> coefficients, the
// split C = sym(C) + A with the symmetric modes, Parseval, and the closed forms evaluated directly.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <random>

#include "icobrdf/core/basis/antisymmetric_modes.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/basis/zernike.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/core/support/error.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using namespace icobrdf;

// Rearrangements of the same O(1) numbers: a few ulps.
constexpr double kAlgebraTol = 1e-13;

Eigen::MatrixXd random_c(int order, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  const int m = hemisphere_basis_count(order);
  Eigen::MatrixXd c(m, m);
  for (Eigen::Index k = 0; k < c.size(); ++k) c.data()[k] = g(rng);
  return c;
}

Eigen::Vector3d dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// sum_ab C_ab K_a(w_i) K_b(w_r).
double evaluate(const Eigen::MatrixXd& c, int order, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) {
  const int m = hemisphere_basis_count(order);
  Eigen::VectorXd ki(m), kr(m);
  hemisphere_basis_eval(order, wi, ki.data());
  hemisphere_basis_eval(order, wr, kr.data());
  return ki.dot(c * kr);
}

TEST(AntisymmetricModes, CountsAndTheSplitOfAGeneralMatrix) {
  for (int order : {0, 1, 2, 5}) {
    const int m = hemisphere_basis_count(order);
    EXPECT_EQ(antisymmetric_mode_count(order), static_cast<long long>(m) * (m - 1) / 2);
    // Symmetric and antisymmetric modes together: M^2 functions, the whole space (paper section 2B).
    EXPECT_EQ(helmholtz_mode_count(order) + antisymmetric_mode_count(order), static_cast<long long>(m) * m);
    const Eigen::MatrixXd c = random_c(order, 7 + order);
    const Eigen::VectorXd z = antisymmetric_from_coefficients(c);
    const Eigen::MatrixXd a = coefficients_from_antisymmetric(order, z);
    EXPECT_LE((a - 0.5 * (c - c.transpose())).cwiseAbs().maxCoeff(), kAlgebraTol);
    EXPECT_LE((coefficients_from_bsss(bsss_from_coefficients(c)) + a - c).cwiseAbs().maxCoeff(), kAlgebraTol * 4);
    EXPECT_NEAR(z.squaredNorm(), a.squaredNorm(), kAlgebraTol * a.squaredNorm());  // Parseval: orthonormal modes
    EXPECT_NEAR(antisymmetric_fraction(c), a.norm() / c.norm(), kAlgebraTol);
  }
  EXPECT_EQ(antisymmetric_fraction(Eigen::MatrixXd::Identity(3, 3)), 0.0);
  EXPECT_THROW(coefficients_from_antisymmetric(2, Eigen::VectorXd(3)), ArgumentError);
  EXPECT_THROW(antisymmetric_from_coefficients(Eigen::MatrixXd(3, 4)), ArgumentError);
}

// A unit coefficient of Z_ab evaluates to (K_a(w_i) K_b(w_r) - K_b(w_i) K_a(w_r)) / sqrt(2), changing sign under the swap.
TEST(AntisymmetricModes, GeneralModesEvaluateToTheirDefinition) {
  const int order = 3, m = hemisphere_basis_count(order);
  const Eigen::Vector3d wi = dir(0.7, 0.3), wr = dir(1.2, 2.5);
  Eigen::VectorXd ki(m), kr(m);
  hemisphere_basis_eval(order, wi, ki.data());
  hemisphere_basis_eval(order, wr, kr.data());
  const long long count = antisymmetric_mode_count(order);
  long long k = 0;
  for (int b = 0; b < m; ++b)
    for (int a = 0; a < b; ++a, ++k) {
      Eigen::VectorXd z = Eigen::VectorXd::Zero(count);
      z[k] = 1.0;
      const Eigen::MatrixXd c = coefficients_from_antisymmetric(order, z);
      const double expected = (ki[a] * kr[b] - ki[b] * kr[a]) * M_SQRT1_2;
      EXPECT_NEAR(evaluate(c, order, wi, wr), expected, kAlgebraTol) << a << " " << b;
      EXPECT_NEAR(evaluate(c, order, wr, wi), -expected, kAlgebraTol) << a << " " << b;
    }
  EXPECT_EQ(k, count);
}

// J_nm^l = 1/(2 pi) sqrt((n+1)(m+1)/A) [R_n^l(rho_i) R_m^l(rho_r) - R_m^l(rho_i) R_n^l(rho_r)] cos(l dphi), A = 2 for
// l = 0 else 1, with rho = sqrt(2) sin(theta/2): a unit coefficient evaluates to it.
TEST(AntisymmetricModes, IsotropicModesEvaluateToTheirClosedForm) {
  const int order = 6;
  const auto modes = isotropic_antisymmetric_modes(order);
  ASSERT_EQ(static_cast<int>(modes.size()), isotropic_antisymmetric_mode_count(order));
  const double ti = 0.9, pi_ = 0.4, tr = 0.35, pr = -1.3;
  const double ri = std::sqrt(2.0) * std::sin(ti / 2), rr = std::sqrt(2.0) * std::sin(tr / 2);
  for (size_t k = 0; k < modes.size(); ++k) {
    const auto [n, m, l] = modes[k];
    ASSERT_GT(n, m);
    Eigen::VectorXd j = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(modes.size()));
    j[static_cast<Eigen::Index>(k)] = 1.0;
    const Eigen::MatrixXd c = coefficients_from_isotropic_antisymmetric(order, j);
    const double a = l == 0 ? 2.0 : 1.0;
    const double expected = 1 / (2 * M_PI) * std::sqrt((n + 1.0) * (m + 1.0) / a) *
                            (zernike_radial(n, l, ri) * zernike_radial(m, l, rr) - zernike_radial(m, l, ri) * zernike_radial(n, l, rr)) *
                            std::cos(l * (pi_ - pr));
    EXPECT_NEAR(evaluate(c, order, dir(ti, pi_), dir(tr, pr)), expected, kAlgebraTol * (n + 1)) << n << m << l;
    EXPECT_NEAR(c.norm(), 1.0, kAlgebraTol);  // unit Frobenius norm: orthonormal
    // Its coefficients give it back.
    EXPECT_LE((isotropic_antisymmetric_from_coefficients(c) - j).cwiseAbs().maxCoeff(), kAlgebraTol);
  }
}

// The isotropic part of a general C splits into its IBSSS (symmetric) and J (antisymmetric) parts exactly.
TEST(AntisymmetricModes, IsotropicPartSplitsIntoSymmetricAndAntisymmetricModes) {
  const int order = 5;
  const Eigen::MatrixXd c = isotropic_part(random_c(order, 3), order);
  const Eigen::MatrixXd sym = coefficients_from_ibsss(order, ibsss_from_coefficients(c));
  const Eigen::MatrixXd anti = coefficients_from_isotropic_antisymmetric(order, isotropic_antisymmetric_from_coefficients(c));
  EXPECT_LE((sym - 0.5 * (c + c.transpose())).cwiseAbs().maxCoeff(), kAlgebraTol * 4);
  EXPECT_LE((anti - 0.5 * (c - c.transpose())).cwiseAbs().maxCoeff(), kAlgebraTol * 4);
  EXPECT_GT(anti.norm(), 0.1 * c.norm());  // a random C has an antisymmetric part: the test can fail
}

}  // namespace ICOBRDF_UNITY_ID
