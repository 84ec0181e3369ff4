// Wavelength-dependent SCATMECH coefficient files (the p column, icobrdf/io/scatmech_coefficients.hpp): each power
// read on its own, evaluated at a wavelength, fitted from spectra at several wavelengths, written and read
// back. The file is written here; the expected coefficients are derived by hand from its rows (the basis
// factor is 1 for n >= m and 1/sqrt(2) for n = 0 < m, docs/readers.md).
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/io/scatmech_coefficients.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::ScratchDir;

// One product or a sum of three per coefficient: a few units in the last place.
constexpr double kRounding = 1e-15;
// The round trip writes 17 significant digits (exact for doubles) and reads them back; the bar.
constexpr double kRoundTrip = 1e-12;
// A polynomial evaluated at three wavelengths and interpolated back: the Vandermonde system of lambdas
// 0.4..0.7 um has condition ~1e3, so the recovered coefficients carry ~1e3 eps.
constexpr double kInterpolation = 1e-12;

const char* kFile =
    "; a file with powers p = 0, 1, 2\n"
    "i,j,n,m,k,l,p,a\n"
    "1,1,0,0,0,0,0,0.1\n"
    "1,1,0,0,0,0,1,0.05\n"
    "1,1,0,0,0,0,2,-0.02\n"
    "1,1,2,0,0,0,1,0.03\n"
    "1,1,0,2,0,0,2,0.04\n"
    "1,1,2,2,2,2,0,0.07\n"
    "1,1,2,2,0,0,1,0.011\n"
    "1,2,1,1,1,1,0,5.0\n";

// Coefficient of mode (N, M, L) of power p, by hand from the rows above.
double by_hand(int p, int n, int m, int l) {
  if (n == 0 && m == 0 && l == 0) return p == 0 ? 0.1 : p == 1 ? 0.05 : -0.02;
  if (n == 2 && m == 0 && l == 0) return p == 1 ? 0.03 : p == 2 ? 0.04 / std::sqrt(2.0) : 0.0;
  if (n == 2 && m == 2 && l == 2) return p == 0 ? 0.07 : 0.0;
  if (n == 2 && m == 2 && l == 0) return p == 1 ? 0.011 : 0.0;
  return 0.0;
}

ScatmechWavelengthPolynomial read_poly(const std::string& path) {
  return scatmech_wavelength_polynomial(read_scatmech_coefficients(path));
}

double max_abs_difference(const ScatmechWavelengthPolynomial& a, const ScatmechWavelengthPolynomial& b) {
  EXPECT_EQ(a.order, b.order);
  EXPECT_EQ(a.ibsss.size(), b.ibsss.size());
  double d = 0;
  for (size_t p = 0; p < std::min(a.ibsss.size(), b.ibsss.size()); ++p) d = std::max(d, (a.ibsss[p] - b.ibsss[p]).cwiseAbs().maxCoeff());
  return d;
}

TEST(ScatmechPolynomial, EachPowerIsReadOnItsOwn) {
  ScratchDir dir;
  std::ofstream(dir / "w.csv") << kFile;
  const auto poly = read_poly(dir / "w.csv");
  ASSERT_EQ(poly.order, 2);
  ASSERT_EQ(poly.ibsss.size(), 3u);
  const auto modes = isotropic_modes(2);
  for (int p = 0; p <= 2; ++p)
    for (size_t k = 0; k < modes.size(); ++k)
      EXPECT_NEAR(poly.ibsss[static_cast<size_t>(p)][static_cast<Eigen::Index>(k)], by_hand(p, modes[k].n, modes[k].m, modes[k].l), kRounding)
          << "p " << p << " mode (" << modes[k].n << ", " << modes[k].m << ", " << modes[k].l << ")";
}

TEST(ScatmechPolynomial, EvaluatesAtAWavelengthAsTheImportDoes) {
  ScratchDir dir;
  std::ofstream(dir / "w.csv") << kFile;
  const auto file = read_scatmech_coefficients(dir / "w.csv");
  const double lambda = 0.633;
  const Eigen::VectorXd b = scatmech_wavelength_polynomial(file).at(lambda);
  ScatmechImportOptions o;
  o.wavelength_um = lambda;
  const Eigen::VectorXd imported = ibsss_from_coefficients(scatmech_to_spectrum(file, o).channels[0]);
  const auto modes = isotropic_modes(2);
  for (size_t k = 0; k < modes.size(); ++k) {
    const auto& md = modes[k];
    const double hand = by_hand(0, md.n, md.m, md.l) + by_hand(1, md.n, md.m, md.l) * lambda + by_hand(2, md.n, md.m, md.l) * lambda * lambda;
    EXPECT_NEAR(b[static_cast<Eigen::Index>(k)], hand, kRounding);
    EXPECT_NEAR(imported[static_cast<Eigen::Index>(k)], hand, kRounding);
  }
}

TEST(ScatmechPolynomial, PowersZeroToTwoRoundTripThroughAFile) {
  ScratchDir dir;
  std::ofstream(dir / "w.csv") << kFile;
  const auto poly = read_poly(dir / "w.csv");
  const std::string text = format_scatmech_polynomial(poly, "test");
  std::ofstream(dir / "out.csv") << text;
  const auto file = read_scatmech_coefficients(dir / "out.csv");
  EXPECT_EQ(file.unpolarized_rows, 3 * isotropic_mode_count(2));  // one row per power and mode
  EXPECT_TRUE(file.wavelength_dependent);
  EXPECT_LE(max_abs_difference(scatmech_wavelength_polynomial(file), poly), kRoundTrip);
}

TEST(ScatmechPolynomial, AFitThroughThreeWavelengthsRecoversTheQuadraticAndRoundTrips) {
  ScratchDir dir;
  std::ofstream(dir / "w.csv") << kFile;
  const auto poly = read_poly(dir / "w.csv");
  const std::vector<double> lambdas{0.4, 0.55, 0.7};
  std::vector<Eigen::VectorXd> at;
  for (double l : lambdas) at.push_back(poly.at(l));
  const auto fitted = fit_wavelength_polynomial(lambdas, at, 2, 2);
  EXPECT_LE(max_abs_difference(fitted, poly), kInterpolation);
  std::ofstream(dir / "fit.csv") << format_scatmech_polynomial(fitted, "fit");
  EXPECT_LE(max_abs_difference(read_poly(dir / "fit.csv"), fitted), kRoundTrip);
  // Degree 1 through the same three spectra is their least-squares line. The constant mode is
  // 0.1 + 0.05 l - 0.02 l^2, and the least-squares line of l^2 over l = 0.4, 0.55, 0.7 is 1.1 l - 0.2875 (by hand:
  // slope sum (l - 0.55)(l^2 - 0.3175) / sum (l - 0.55)^2 = 0.0495 / 0.045, intercept 0.3175 - 1.1 * 0.55).
  const auto line = fit_wavelength_polynomial(lambdas, at, 2, 1);
  ASSERT_EQ(line.ibsss.size(), 2u);
  EXPECT_NEAR(line.ibsss[1][0], 0.05 - 0.02 * 1.1, kInterpolation);
  EXPECT_NEAR(line.ibsss[0][0], 0.1 + 0.02 * 0.2875, kInterpolation);
}

TEST(ScatmechPolynomial, FitsThatTheWavelengthsCannotDetermineAreRefused) {
  const std::vector<Eigen::VectorXd> two{Eigen::VectorXd::Ones(1), Eigen::VectorXd::Ones(1)};
  EXPECT_THROW(fit_wavelength_polynomial({0.5, 0.6}, two, 0, 2), ArgumentError);  // 2 wavelengths, 3 unknowns
  EXPECT_THROW(fit_wavelength_polynomial({0.5, 0.5}, two, 0, 1), ArgumentError);  // repeated
  EXPECT_THROW(fit_wavelength_polynomial({0.5, 0.6}, two, 0, 5), ArgumentError);  // beyond SCATMECH's p
  EXPECT_THROW(fit_wavelength_polynomial({0.5, -0.6}, two, 0, 1), ArgumentError);
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
