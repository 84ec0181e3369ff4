// General Helmholtz modes: counts, order, C <-> BSSS, evaluation (eq. 19), orthonormality by exact quadrature.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cmath>
#include <iostream>
#include <random>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "tests/core/hemisphere_quadrature.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using namespace icobrdf;

// Gram matrix of H on an exact product quadrature: sums of ~1e4 products of O(1) values.
constexpr double kGramTol = 1e-12;
// Rearrangements of the same floating-point numbers (C <-> BSSS, sums of a few products): a few ulps of
// the largest magnitude involved.
constexpr double kAlgebraTol = 1e-13;

Eigen::Vector3d dir(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

Eigen::MatrixXd random_matrix(int m, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  Eigen::MatrixXd c(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) c(i, j) = g(rng);
  return c;
}

TEST(HelmholtzModes, CountsFromDefinitions) {
  // M(M+1)/2 with M = (N+1)(N+2)/2: the paper's 14, 55, 295 (section 2C) do not follow (docs/errata.md).
  EXPECT_EQ(helmholtz_mode_count(0), 1);
  EXPECT_EQ(helmholtz_mode_count(2), 21);
  EXPECT_EQ(helmholtz_mode_count(4), 120);
  EXPECT_EQ(helmholtz_mode_count(8), 1035);
  EXPECT_EQ(helmholtz_mode_count(128), 8385LL * 8386 / 2);
  EXPECT_THROW(helmholtz_mode_count(-1), ArgumentError);
  EXPECT_THROW(helmholtz_mode_count(129), ArgumentError);
}

TEST(HelmholtzModes, LibraryOrderIsColumnWiseAndTruncationIsAPrefix) {
  const auto m4 = helmholtz_modes(4), m2 = helmholtz_modes(2);
  ASSERT_EQ(static_cast<long long>(m4.size()), helmholtz_mode_count(4));
  for (size_t k = 0; k < m2.size(); ++k) {
    EXPECT_EQ(m2[k].a, m4[k].a);
    EXPECT_EQ(m2[k].b, m4[k].b);
  }
  long long k = 0;
  for (int b = 0; b < hemisphere_basis_count(4); ++b)
    for (int a = 0; a <= b; ++a, ++k) {
      const auto& h = m4[static_cast<size_t>(k)];
      EXPECT_EQ(h.a, a);
      EXPECT_EQ(h.b, b);
      EXPECT_EQ(helmholtz_mode_index(a, b), k);
      EXPECT_EQ(helmholtz_mode_index(b, a), k);
      EXPECT_EQ(ansi_index(h.n, h.l), a);
      EXPECT_EQ(ansi_index(h.m, h.lp), b);
    }
  // helmholtz_mode_at inverts the index, here and at the last mode of order 128 (index 35158304).
  for (size_t i = 0; i < m4.size(); ++i) {
    const auto h = helmholtz_mode_at(static_cast<long long>(i));
    EXPECT_EQ(h.a, m4[i].a);
    EXPECT_EQ(h.b, m4[i].b);
    EXPECT_EQ(h.lp, m4[i].lp);
  }
  const auto last = helmholtz_mode_at(helmholtz_mode_count(128) - 1);
  EXPECT_EQ(last.a, 8384);
  EXPECT_EQ(last.b, 8384);
  EXPECT_EQ(last.n, 128);
  EXPECT_EQ(last.l, 128);
  EXPECT_THROW(helmholtz_mode_at(-1), ArgumentError);
  // First modes: (K_0^0, K_0^0), (K_0^0, K_1^-1), (K_1^-1, K_1^-1), (K_0^0, K_1^1), ...
  EXPECT_EQ(m4[1].m, 1);
  EXPECT_EQ(m4[1].lp, -1);
  EXPECT_EQ(m4[3].a, 0);
  EXPECT_EQ(m4[3].lp, 1);
}

TEST(HelmholtzModes, CoefficientRoundTripAndEnergy) {
  const int m = hemisphere_basis_count(6);
  const Eigen::MatrixXd raw = random_matrix(m, 5);
  const Eigen::MatrixXd sym = 0.5 * (raw + raw.transpose());
  const Eigen::VectorXd v = bsss_from_coefficients(sym);
  ASSERT_EQ(v.size(), helmholtz_mode_count(6));
  EXPECT_LE((coefficients_from_bsss(v) - sym).cwiseAbs().maxCoeff(), kAlgebraTol);
  // Parseval: the BSSS carries the energy of the (symmetric) C.
  EXPECT_NEAR(v.squaredNorm(), sym.squaredNorm(), kAlgebraTol * sym.squaredNorm());
  // a_ab = sqrt(2) C_ab for a < b, C_aa on the diagonal (eq. 21 with eq. 18).
  EXPECT_NEAR(v[helmholtz_mode_index(2, 7)], std::sqrt(2.0) * sym(2, 7), kAlgebraTol);
  EXPECT_NEAR(v[helmholtz_mode_index(7, 7)], sym(7, 7), kAlgebraTol);
  // A non-reciprocal C is projected onto its symmetric part.
  EXPECT_LE((bsss_from_coefficients(raw) - v).cwiseAbs().maxCoeff(), kAlgebraTol);
  // Orthonormality of the mode coefficient matrices at order 64: BSSS(C(v)) = v for a random v means the
  // matrices E_k of the modes have identity Gram matrix; with K orthonormal, so are the modes.
  const long long big = helmholtz_mode_count(64);
  std::mt19937_64 rng(9);
  std::normal_distribution<double> g;
  Eigen::VectorXd w(big);
  for (long long i = 0; i < big; ++i) w[i] = g(rng);
  EXPECT_LE((bsss_from_coefficients(coefficients_from_bsss(w)) - w).cwiseAbs().maxCoeff(), kAlgebraTol);
}

TEST(HelmholtzModes, EvaluationMatchesEquation19AndReconstruction) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> th(0.0, M_PI / 2), ph(-M_PI, M_PI);
  const int order = 4;
  const int m = hemisphere_basis_count(order);
  const Eigen::MatrixXd raw = random_matrix(m, 21);
  const Eigen::MatrixXd c = 0.5 * (raw + raw.transpose());
  const Eigen::VectorXd bsss = bsss_from_coefficients(c);
  RowMatrix3d wi(50, 3), wr(50, 3);
  std::vector<double> ti, pi_, tr, pr;
  for (int r = 0; r < 50; ++r) {
    ti.push_back(th(rng)), pi_.push_back(ph(rng)), tr.push_back(th(rng)), pr.push_back(ph(rng));
    wi.row(r) = dir(ti.back(), pi_.back());
    wr.row(r) = dir(tr.back(), pr.back());
  }
  const Eigen::MatrixXd h = helmholtz_modes_eval(order, wi, wr);
  const Eigen::MatrixXd h_swapped = helmholtz_modes_eval(order, wr, wi);
  const Eigen::MatrixXd ki = hemisphere_basis_matrix(order, wi), kr = hemisphere_basis_matrix(order, wr);
  ASSERT_EQ(h.cols(), helmholtz_mode_count(order));
  for (int r = 0; r < 50; ++r) {
    // Eq. (19) for the mode n = 1, k = 1 (K_1^1), m = 2, l = -2 (K_2^-2), with R_1^1 = rho, R_2^2 = rho^2,
    // az_1 = cos phi, az_-2 = sin 2 phi: (1/pi) sqrt(2 * 3 / 2) [rho_i rho_r^2 cos(phi_i) sin(2 phi_r) + swap].
    const double ri = std::sqrt(2.0) * std::sin(ti[r] / 2), rr = std::sqrt(2.0) * std::sin(tr[r] / 2);
    const double eq19 = std::sqrt(3.0) / M_PI *
                        (ri * rr * rr * std::cos(pi_[r]) * std::sin(2 * pr[r]) +
                         ri * ri * rr * std::sin(2 * pi_[r]) * std::cos(pr[r]));
    EXPECT_NEAR(h(r, helmholtz_mode_index(ansi_index(1, 1), ansi_index(2, -2))), eq19, kAlgebraTol);
    // Diagonal mode K_2^0 x K_2^0: (3/pi) (2 rho_i^2 - 1)(2 rho_r^2 - 1) / 2 (the delta in eq. 19 gives 1/4).
    const double eq19d = 3.0 / M_PI * (2 * ri * ri - 1) * (2 * rr * rr - 1) / 2.0;
    EXPECT_NEAR(h(r, helmholtz_mode_index(ansi_index(2, 0), ansi_index(2, 0))), eq19d, kAlgebraTol);
    // Reciprocity of every mode and f = sum C_ab K_a K_b = sum_k a_k H_k.
    EXPECT_LE((h.row(r) - h_swapped.row(r)).cwiseAbs().maxCoeff(), kAlgebraTol);
    const double f = ki.row(r) * c * kr.row(r).transpose();
    EXPECT_NEAR(h.row(r).dot(bsss), f, kAlgebraTol * 100);  // ~120 terms of size up to ~5
  }
  RowMatrix3d one(1, 3);
  one.row(0) = dir(0.3, 0.2);
  EXPECT_THROW(helmholtz_modes_eval(order, wi, one), ArgumentError);
}

TEST(HelmholtzModes, OrthonormalByExactProductQuadrature) {
  // The product of two rules exact for K to order N (tests/core/hemisphere_quadrature.hpp) is exact for
  // integrals of H_k H_k' over hemisphere x hemisphere (Fubini). Order 6: 406 modes on 70 x 70 = 4900
  // pairs (a 4900 x 406 matrix); order 8 would need 11664 x 1035 (~100 MB) for no new information, since
  // the K Gram error at order 64 (test_hemisphere_basis) and the exact orthonormality of the mode
  // coefficient matrices (CoefficientRoundTripAndEnergy, order 64) together imply it for every order <= 64.
  for (int order : {2, 6}) {
    const auto pairs = test::pair_rule(test::hemisphere_rule_for_order(order));
    const Eigen::MatrixXd b = pairs.w.cwiseSqrt().asDiagonal() * helmholtz_modes_eval(order, pairs.wi, pairs.wr);
    Eigen::MatrixXd g = Eigen::MatrixXd::Zero(b.cols(), b.cols());
    g.selfadjointView<Eigen::Lower>().rankUpdate(b.transpose());
    g.triangularView<Eigen::StrictlyUpper>() = g.transpose();
    const double err = (g - Eigen::MatrixXd::Identity(b.cols(), b.cols())).cwiseAbs().maxCoeff();
    std::cout << "Helmholtz order " << order << " (" << b.cols() << " modes): max |G - I| = " << err << "\n";
    EXPECT_LE(err, kGramTol);
  }
}

TEST(HelmholtzModes, RejectsBadSizes) {
  EXPECT_THROW(bsss_from_coefficients(Eigen::MatrixXd::Zero(5, 5)), ArgumentError);   // 5 is no basis count
  EXPECT_THROW(bsss_from_coefficients(Eigen::MatrixXd::Zero(6, 3)), ArgumentError);   // not square
  EXPECT_THROW(coefficients_from_bsss(Eigen::VectorXd::Zero(20)), ArgumentError);     // 20 is no mode count
  EXPECT_THROW(helmholtz_mode_index(-1, 0), ArgumentError);
}

}  // namespace ICOBRDF_UNITY_ID
