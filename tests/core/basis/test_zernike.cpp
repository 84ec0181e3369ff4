// Zernike radial polynomials: accuracy to order 128 against 100-digit references, layout, identities.
#include <gtest/gtest.h>

#include <boost/multiprecision/cpp_bin_float.hpp>

#include <cmath>
#include <iostream>
#include <random>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/zernike.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::zernike_radial;
using icobrdf::zernike_radial_all;
using icobrdf::zernike_radial_count;
using icobrdf::zernike_radial_index;
using Mp = boost::multiprecision::cpp_bin_float_100;

constexpr int kMaxOrder = 128;
// The required accuracy: absolute error of every R_n^l, n <= 128, rho in [0, 1].
constexpr double kAbsTol = 1e-13;
// R_n^l(1) = 1 and R_n^l(0) in {0, +-1}: the recurrence only adds and subtracts exact ones/zeros there.
constexpr double kExactTol = 0.0;

// Reference: the closed factorial sum (eq. 3) in 100-digit arithmetic. Its coefficients reach ~1e37 at
// n = 128, so double arithmetic loses everything; 332 mantissa bits leave > 60 correct digits.
// c_s = (-1)^s (n-s)! / (s! ((n+l)/2 - s)! ((n-l)/2 - s)!),  c_{s+1}/c_s = -(k-s)(j-s) / ((s+1)(n-s)),
// R = rho^l sum_s c_s (rho^2)^(j-s) with k = (n+l)/2, j = (n-l)/2 (Horner in rho^2).
struct MpReference {
  std::vector<std::vector<Mp>> coeffs;  // packed like the library, coefficients c_0 .. c_j
  std::vector<int> n_of, l_of;
  MpReference() {
    for (int n = 0; n <= kMaxOrder; ++n)
      for (int l = n % 2; l <= n; l += 2) {
        const int k = (n + l) / 2, j = (n - l) / 2;
        std::vector<Mp> c(static_cast<size_t>(j + 1));
        Mp c0 = 1;  // n! / (k! j!) = binomial(n, j)
        for (int t = 1; t <= j; ++t) c0 = c0 * (n - j + t) / t;
        c[0] = c0;
        for (int s = 0; s < j; ++s) c[s + 1] = -c[s] * (k - s) * (j - s) / ((s + 1) * (n - s));
        coeffs.push_back(std::move(c));
        n_of.push_back(n);
        l_of.push_back(l);
      }
  }
  double eval(size_t idx, double rho_d) const {
    const Mp rho = rho_d, rho2 = rho * rho;
    const auto& c = coeffs[idx];
    Mp acc = c[0];
    for (size_t s = 1; s < c.size(); ++s) acc = acc * rho2 + c[s];
    return static_cast<double>(acc * boost::multiprecision::pow(rho, l_of[idx]));
  }
};

const MpReference& reference() {
  static const MpReference ref;
  return ref;
}

TEST(Zernike, CountsAndPackedLayout) {
  EXPECT_EQ(zernike_radial_count(0), 1);
  EXPECT_EQ(zernike_radial_count(1), 2);
  EXPECT_EQ(zernike_radial_count(2), 4);
  EXPECT_EQ(zernike_radial_count(kMaxOrder), 4225);  // sum_{n<=128} (floor(n/2)+1) = 65^2
  int expected = 0;                                   // n ascending, then l ascending
  for (int n = 0; n <= kMaxOrder; ++n)
    for (int l = n % 2; l <= n; l += 2) EXPECT_EQ(zernike_radial_index(n, l), expected++);
  EXPECT_EQ(expected, zernike_radial_count(kMaxOrder));
}

TEST(Zernike, LowOrderClosedForms) {
  // Textbook polynomials (Born & Wolf): R_2^0 = 2r^2-1, R_3^1 = 3r^3-2r, R_4^0 = 6r^4-6r^2+1, R_4^2 = 4r^4-3r^2.
  constexpr double kTol = 1e-15;  // a few ulps of O(1) values
  for (double r : {0.0, 0.1, 0.5, 0.77, 1.0}) {
    EXPECT_NEAR(zernike_radial(0, 0, r), 1.0, kTol);
    EXPECT_NEAR(zernike_radial(1, 1, r), r, kTol);
    EXPECT_NEAR(zernike_radial(2, 0, r), 2 * r * r - 1, kTol);
    EXPECT_NEAR(zernike_radial(2, 2, r), r * r, kTol);
    EXPECT_NEAR(zernike_radial(3, 1, r), 3 * r * r * r - 2 * r, kTol);
    EXPECT_NEAR(zernike_radial(4, 0, r), 6 * std::pow(r, 4) - 6 * r * r + 1, kTol);
    EXPECT_NEAR(zernike_radial(4, 2, r), 4 * std::pow(r, 4) - 3 * r * r, kTol);
  }
}

TEST(Zernike, AllOrdersTo128AgainstHighPrecisionReference) {
  const auto& ref = reference();
  std::vector<double> rhos = {0.0, 1.0, 1e-300, 1e-8, 0.5, M_SQRT1_2, 0.9, 0.99, 0.999, 0.9999, 1.0 - 1e-12,
                              std::sqrt(2.0) * std::sin(M_PI / 360.0), std::nextafter(1.0, 0.0)};
  std::mt19937_64 rng(20260522);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  for (int i = 0; i < 40; ++i) rhos.push_back(uni(rng));
  for (int i = 0; i < 12; ++i) rhos.push_back(1.0 - 0.05 * uni(rng));  // the oscillatory region near the rim
  std::vector<double> got(static_cast<size_t>(zernike_radial_count(kMaxOrder)));
  double worst = 0.0, worst_rho = 0.0;
  int worst_n = -1, worst_l = -1;
  for (double rho : rhos) {
    zernike_radial_all(kMaxOrder, rho, got.data());
    for (size_t k = 0; k < got.size(); ++k) {
      const double err = std::abs(got[k] - ref.eval(k, rho));
      if (err > worst) {
        worst = err;
        worst_rho = rho;
        worst_n = ref.n_of[k];
        worst_l = ref.l_of[k];
      }
    }
  }
  std::cout << "max |R - R_ref| over n <= 128, " << rhos.size() << " radii: " << worst << " at n = " << worst_n
            << ", l = " << worst_l << ", rho = " << worst_rho << "\n";
  RecordProperty("max_abs_error", std::to_string(worst));
  EXPECT_LE(worst, kAbsTol);
}

TEST(Zernike, ClosedSumInDoubleFailsWhereRecurrenceHolds) {
  // Documents why the closed sum is not used: evaluated in double at n = 60, l = 0 it is far off the
  // reference while the recurrence is not (this test fails if the reason for the recurrence disappears).
  const auto& ref = reference();
  const int n = 60, l = 0;
  const double rho = 0.83;
  double sum = 0.0;
  for (int s = 0; s <= (n - l) / 2; ++s)
    sum += std::pow(-1.0, s) * std::tgamma(n - s + 1.0) /
           (std::tgamma(s + 1.0) * std::tgamma((n + l) / 2 - s + 1.0) * std::tgamma((n - l) / 2 - s + 1.0)) *
           std::pow(rho, n - 2 * s);
  const double exact = ref.eval(static_cast<size_t>(zernike_radial_index(n, l)), rho);
  EXPECT_GT(std::abs(sum - exact), 1e-6);
  EXPECT_LE(std::abs(zernike_radial(n, l, rho) - exact), kAbsTol);
}

TEST(Zernike, ValueAtRimIsOneAndAtCentreIsKnown) {
  std::vector<double> at1(static_cast<size_t>(zernike_radial_count(kMaxOrder)));
  std::vector<double> at0(at1.size());
  zernike_radial_all(kMaxOrder, 1.0, at1.data());
  zernike_radial_all(kMaxOrder, 0.0, at0.data());
  for (int n = 0; n <= kMaxOrder; ++n)
    for (int l = n % 2; l <= n; l += 2) {
      const auto k = static_cast<size_t>(zernike_radial_index(n, l));
      EXPECT_NEAR(at1[k], 1.0, kExactTol) << n << " " << l;
      // R_n^l(0) = 0 for l > 0; R_n^0(0) = (-1)^(n/2) (the constant term c_{n/2} of eq. 3).
      const double centre = l > 0 ? 0.0 : ((n / 2) % 2 == 0 ? 1.0 : -1.0);
      EXPECT_NEAR(at0[k], centre, kExactTol) << n << " " << l;
    }
}

TEST(Zernike, EvenRadialIsShiftedLegendre) {
  // Eq. (30): R_2n^0(rho) = P_n(2 rho^2 - 1), P_n by Bonnet's recurrence (k+1) P_{k+1} = (2k+1) x P_k - k P_{k-1}.
  constexpr double kLegendreTol = 2e-14;  // both sides carry ~ n ulps of rounding, n <= 64
  std::vector<double> all(static_cast<size_t>(zernike_radial_count(kMaxOrder)));
  for (double rho : {0.0, 0.05, 0.3, 0.5, 0.6180339887, 0.8, 0.95, 0.999, 1.0}) {
    zernike_radial_all(kMaxOrder, rho, all.data());
    const double x = 2 * rho * rho - 1;
    double p_prev = 1.0, p = x;
    EXPECT_NEAR(all[static_cast<size_t>(zernike_radial_index(0, 0))], 1.0, kLegendreTol);
    for (int k = 1; k <= kMaxOrder / 2; ++k) {
      EXPECT_NEAR(all[static_cast<size_t>(zernike_radial_index(2 * k, 0))], p, kLegendreTol) << k << " " << rho;
      const double next = ((2 * k + 1) * x * p - k * p_prev) / (k + 1);
      p_prev = p;
      p = next;
    }
  }
}

TEST(Zernike, SingleValueMatchesPackedArray) {
  std::vector<double> all(static_cast<size_t>(zernike_radial_count(40)));
  zernike_radial_all(40, 0.37, all.data());
  for (int n = 0; n <= 40; ++n)
    for (int l = n % 2; l <= n; l += 2)
      EXPECT_EQ(zernike_radial(n, l, 0.37), all[static_cast<size_t>(zernike_radial_index(n, l))]);
}

TEST(Zernike, RejectsInvalidArguments) {
  std::vector<double> buf(8000);
  EXPECT_THROW(zernike_radial_count(-1), icobrdf::ArgumentError);
  EXPECT_THROW(zernike_radial_count(129), icobrdf::ArgumentError);
  EXPECT_THROW(zernike_radial_index(3, 0), icobrdf::ArgumentError);   // n - l odd
  EXPECT_THROW(zernike_radial_index(2, 4), icobrdf::ArgumentError);   // l > n
  EXPECT_THROW(zernike_radial_index(2, -2), icobrdf::ArgumentError);  // radial index is |l|
  EXPECT_THROW(zernike_radial_all(-1, 0.5, buf.data()), icobrdf::ArgumentError);
  EXPECT_THROW(zernike_radial_all(4, 1.5, buf.data()), icobrdf::ArgumentError);
  EXPECT_THROW(zernike_radial_all(4, -0.1, buf.data()), icobrdf::ArgumentError);
  EXPECT_THROW(zernike_radial_all(4, std::nan(""), buf.data()), icobrdf::ArgumentError);
  EXPECT_THROW(zernike_radial(130, 0, 0.5), icobrdf::ArgumentError);
  // A radius a rounding step above 1 (from a horizon direction) is accepted as the rim.
  EXPECT_NO_THROW(zernike_radial_all(4, 1.0 + 1e-15, buf.data()));
  EXPECT_EQ(buf[0], 1.0);
}

}  // namespace ICOBRDF_UNITY_ID
