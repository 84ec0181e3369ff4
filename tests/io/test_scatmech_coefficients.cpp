// SCATMECH ZernikeExpansion_BRDF_Model coefficient files (icobrdf/io/scatmech_coefficients.hpp).
//
// The reference evaluation below implements SCATMECH's definition on its own terms (its documentation's
// formula with the azimuthal order from column l, as its source code reads it): explicit factorial sum for
// R_n^l, SCATMECH's A^S, and its geometry (incident vector at azimuth pi, scattered vector at phi_s, sample
// rotation 0). It shares no code with icobrdf's Zernike recurrence, isotropic modes or coefficient mapping.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>
#include <sstream>

#include "icobrdf/core/spectrum/analytic_spectra.hpp"
#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/direction_csv.hpp"
#include "icobrdf/io/scatmech_coefficients.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

using test::ScratchDir;

// Both sides evaluate order <= 8 polynomials of O(1) coefficients: agreement to rounding, relative to
// the sum of absolute term values.
constexpr double kEvalTol = 1e-11;

long double fact(int n) {
  long double f = 1;
  for (int k = 2; k <= n; ++k) f *= k;
  return f;
}

// R_n^m(rho) = sum_s (-1)^s (n-s)! / (s! ((n+m)/2-s)! ((n-m)/2-s)!) rho^(n-2s)
long double radial(int n, int l, long double rho) {
  const int m = std::abs(l);
  if ((n - m) % 2 != 0 || m > n) return 0;
  long double sum = 0;
  for (int s = 0; s <= (n - m) / 2; ++s)
    sum += ((s % 2) ? -1.0L : 1.0L) * fact(n - s) / (fact(s) * fact((n + m) / 2 - s) * fact((n - m) / 2 - s)) *
           std::pow(rho, static_cast<long double>(n - 2 * s));
  return sum;
}

struct Row {
  int i, j, n, m, k, l, p;
  double a;
};

// f_11 at (theta_i, theta_s, phi_s) by SCATMECH's definition; `mag` collects sum |term| for the tolerance.
double scatmech_f11(const std::vector<Row>& rows, double lambda, double scale, double ti, double ts, double ps, double& mag) {
  const long double rhoi = std::sqrt(2.0L) * std::sin(ti / 2.0L), rhor = std::sqrt(2.0L) * std::sin(ts / 2.0L);
  const long double phii = M_PI, phir = ps;
  long double f = 0;
  mag = 0;
  for (const Row& r : rows) {
    if (r.i != 1 || r.j != 1) continue;
    const int n = r.n, m = r.m, l = r.l;
    const double A = (n == 0 || (n == m && l == 0)) ? 4.0 : ((n == m || l == 0) ? 2.0 : 1.0);
    const long double pre = 0.5L / M_PI * std::sqrt((n + 1.0L) * (m + 1.0L) / A) * std::pow(static_cast<long double>(lambda), r.p);
    const long double t = r.a * pre * (radial(n, l, rhoi) * radial(m, l, rhor) + radial(m, l, rhoi) * radial(n, l, rhor)) *
                          std::cos(l * (phir - phii));
    f += t;
    mag += static_cast<double>(std::abs(t));
  }
  return static_cast<double>(f * scale);
}

std::string write_rows(const std::string& file, const std::vector<Row>& rows, const std::string& head = "") {
  std::ofstream o(file);
  o << head;
  for (const Row& r : rows) {
    char b[200];
    std::snprintf(b, sizeof b, "%d,%d,%d,%d,%d,%d,%d,%.17g\n", r.i, r.j, r.n, r.m, r.k, r.l, r.p, r.a);
    o << b;
  }
  return file;
}

double ours(const Spectrum& s, double ti, double ts, double ps) {
  RowMatrix3d wi(1, 3), wr(1, 3);
  wi.row(0) = direction_from_angles(ti, M_PI).transpose();
  wr.row(0) = direction_from_angles(ts, ps).transpose();
  return evaluate_coefficients(s.channels[0], s.order, wi, wr)[0];
}

// Random valid 11 rows of order <= 8, including n < m, n = 0 < m, negative l, k != l and p = 0..2, plus
// rows of other Mueller elements (which must not change f_11).
std::vector<Row> random_rows(unsigned seed) {
  std::mt19937 g(seed);
  std::uniform_int_distribution<int> ord(0, 8), pw(0, 2);
  std::normal_distribution<double> nd(0, 1);
  std::vector<Row> rows;
  while (rows.size() < 60) {
    const int n = ord(g), m = ord(g);
    if ((n - m) % 2) continue;
    const int lmax = std::min(n, m);
    std::uniform_int_distribution<int> ll(0, lmax / 2);
    int l = lmax - 2 * ll(g);
    if (g() % 3 == 0) l = -l;
    rows.push_back({1, 1, n, m, (g() % 4 == 0) ? 0 : l, l, pw(g), nd(g)});
  }
  rows.push_back({1, 1, 0, 2, 0, 0, 0, 0.7});  // n = 0 < m: SCATMECH's A = 4, ours 2
  rows.push_back({1, 2, 3, 1, 1, -1, 0, 5.0});
  rows.push_back({2, 2, 2, 2, 2, 2, 1, -3.0});
  rows.push_back({3, 4, 1, 1, -1, 1, 0, 2.0});
  return rows;
}

TEST(ScatmechCoefficients, ImportMatchesScatmechDefinitionAtRandomGeometries) {
  ScratchDir d;
  const auto rows = random_rows(1);
  write_rows(d / "c.csv", rows, "; test coefficients\ni,j,n,m,k,l,p,a\n");
  const ScatmechCoefficients f = read_scatmech_coefficients(d / "c.csv");
  EXPECT_EQ(f.unpolarized_rows, 61);
  EXPECT_EQ(f.polarized_rows, 3);
  EXPECT_EQ(f.order, 8);
  EXPECT_TRUE(f.wavelength_dependent);
  long long kd = 0;
  for (const auto& r : rows) kd += (r.i == 1 && r.j == 1 && r.k != r.l);
  EXPECT_EQ(f.k_differs_rows, kd);
  ScatmechImportOptions o;
  o.wavelength_um = 0.6328;
  o.scale = 0.93;
  const Spectrum s = scatmech_to_spectrum(f, o);
  EXPECT_TRUE(s.isotropic);
  EXPECT_EQ(s.order, 8);
  std::mt19937 g(2);
  std::uniform_real_distribution<double> th(0.0, M_PI / 2), ph(-M_PI, M_PI);
  for (int t = 0; t < 300; ++t) {
    const double ti = th(g), ts = th(g), ps = ph(g);
    double mag = 0;
    const double want = scatmech_f11(rows, 0.6328, 0.93, ti, ts, ps, mag);
    EXPECT_NEAR(ours(s, ti, ts, ps), want, kEvalTol * mag * 0.93) << ti << " " << ts << " " << ps;
  }
  // Grazing, normal and specular geometries.
  for (const auto& geo : std::vector<std::array<double, 3>>{{0, 0, 0}, {M_PI / 2, M_PI / 2, 0}, {0.3, 0.3, 0}, {1.2, 0.0, 2.0}}) {
    double mag = 0;
    const double want = scatmech_f11(rows, 0.6328, 0.93, geo[0], geo[1], geo[2], mag);
    EXPECT_NEAR(ours(s, geo[0], geo[1], geo[2]), want, kEvalTol * mag * 0.93);
  }
}

TEST(ScatmechCoefficients, RecognizedByContentWhateverTheName) {
  ScratchDir d;
  const auto rows = random_rows(3);
  // NIST's names, a headerless file and a .txt: all SCATMECH files by content.
  write_rows(d / "ptfe.coeff.csv", rows, "; NIST PTFE\ni,j,n,m,k,l,p,a\n");
  write_rows(d / "ptfe.coef.csv", rows);
  write_rows(d / "ptfe.txt", rows, "\n# comment\n");
  for (const char* name : {"ptfe.coeff.csv", "ptfe.coef.csv", "ptfe.txt"}) {
    EXPECT_TRUE(looks_like_scatmech_coefficients(d / name)) << name;
    const auto src = open_source(d / name + "#lambda=0.6328");
    EXPECT_EQ(src->channels(), 1);
    // The 3 polarized rows are counted, not dropped silently.
    const auto notes = src->notes();
    ASSERT_FALSE(notes.empty()) << name;
    EXPECT_NE(notes[0].find("3 row(s) of polarized Mueller elements"), std::string::npos) << notes[0];
    EXPECT_NE(notes[0].find("61 row(s)"), std::string::npos) << notes[0];
  }
  // A sample CSV stays a sample CSV; binary bytes and missing files are not coefficient files.
  test::write_bytes(d / "s.csv", "theta_i,phi_i,theta_r,phi_r,f\n10,0,20,180,0.3\n");
  EXPECT_FALSE(looks_like_scatmech_coefficients(d / "s.csv"));
  EXPECT_THROW(open_source(d / "s.csv")->eval(RowMatrix3d::Zero(1, 3), RowMatrix3d::Zero(1, 3)), ArgumentError);  // samples: fit first
  test::write_bytes(d / "b.h5", std::string("\x89HDF\r\n\x1a\n\0\0\0", 11));
  EXPECT_FALSE(looks_like_scatmech_coefficients(d / "b.h5"));
  EXPECT_FALSE(looks_like_scatmech_coefficients(d / "absent.csv"));
  // Seven fields, or a non-integer index, is not a coefficient row.
  test::write_bytes(d / "seven.txt", "1,1,0,0,0,0,0\n");
  EXPECT_FALSE(looks_like_scatmech_coefficients(d / "seven.txt"));
  test::write_bytes(d / "real.txt", "1,1,0.5,0,0,0,0,1\n");
  EXPECT_FALSE(looks_like_scatmech_coefficients(d / "real.txt"));
}

TEST(ScatmechCoefficients, EvalInScatmechGeometryMatchesItsDefinition) {
  // Pairs given as SCATMECH's (thetai, thetas, phis, rotation), signed angles included, evaluated through the
  // SOURCE; the reference is SCATMECH's definition at the geometrically equal unsigned angles: a negative
  // thetai puts the source at azimuth 0 and a negative thetas turns phis by pi, so the relative azimuth
  // gains pi for each; the rotation of an isotropic expansion changes nothing.
  ScratchDir d;
  const auto rows = random_rows(4);
  write_rows(d / "g.coef.csv", rows);
  const auto src = open_source(d / "g.coef.csv#lambda=0.6328");
  std::mt19937 g(5);
  std::uniform_real_distribution<double> th(-89.0, 89.0), ph(-180.0, 180.0);
  std::ostringstream csv;
  csv.precision(17);
  csv << "thetai,thetas,phis,rotation\n";
  std::vector<std::array<double, 3>> geo;
  for (int t = 0; t < 100; ++t) {
    const double ti = th(g), ts = th(g), ps = ph(g), rot = ph(g);
    csv << ti << "," << ts << "," << ps << "," << rot << "\n";
    const double deg = M_PI / 180;
    geo.push_back({std::abs(ti) * deg, std::abs(ts) * deg, ps * deg + M_PI * ((ti < 0) + (ts < 0))});
  }
  test::write_bytes(d / "pairs.csv", csv.str());
  const DirectionPairs p = read_direction_pairs_csv(d / "pairs.csv");
  const Eigen::MatrixXd v = src->eval(p.wi, p.wr);
  for (int t = 0; t < 100; ++t) {
    double mag = 0;
    const double want = scatmech_f11(rows, 0.6328, 1.0, geo[t][0], geo[t][1], geo[t][2], mag);
    EXPECT_NEAR(v(t, 0), want, kEvalTol * mag) << t;
  }
}

// One row 1,1,0,0,0,0,0,2: SCATMECH's I_00^0 = (1/2pi) sqrt(1/4) * 2 = 1/(2pi), so f = 1/pi, the unit-albedo
// Lambert surface whose only coefficient is C_00 = 2 (SPEC-NOTES).
TEST(ScatmechCoefficients, LambertRow) {
  ScratchDir d;
  write_rows(d / "l.csv", {{1, 1, 0, 0, 0, 0, 0, 2.0}});
  const Spectrum s = scatmech_to_spectrum(read_scatmech_coefficients(d / "l.csv"));
  EXPECT_EQ(s.order, 0);
  EXPECT_NEAR(s.channels[0](0, 0), lambert_coefficients(0)(0, 0), 1e-15);
  EXPECT_NEAR(ours(s, 0.4, 1.1, 0.3), 1 / M_PI, 1e-15);
}

TEST(ScatmechCoefficients, ExportRoundTripAndIndependentEvaluation) {
  ScratchDir d;
  const int order = 6;
  std::mt19937 g(3);
  std::normal_distribution<double> nd(0, 1);
  Eigen::VectorXd b(isotropic_mode_count(order));
  for (Eigen::Index k = 0; k < b.size(); ++k) b[k] = nd(g);
  Spectrum s;
  s.order = order;
  s.isotropic = true;
  s.source = "test";
  s.channels = {Eigen::MatrixXd::Zero(1, 1), coefficients_from_ibsss(order, b)};
  s.channels[0] = 0.5 * s.channels[1];
  const ScatmechExport e = write_scatmech_coefficients(d / "out.csv", s, 1, false);
  EXPECT_EQ(e.rows, isotropic_mode_count(order));
  EXPECT_LT(e.anisotropic_fraction, kScatmechIsotropyTolerance);
  const std::string text = test::read_bytes(d / "out.csv");
  EXPECT_EQ(text.find('\r'), std::string::npos);
  EXPECT_EQ(text.rfind("; SCATMECH", 0), 0u);
  // Re-import: the same coefficient matrix (17-digit numbers read back exactly; C <-> IBSSS rounding).
  const ScatmechCoefficients f = read_scatmech_coefficients(d / "out.csv");
  EXPECT_EQ(f.k_differs_rows, 0);
  const Spectrum back = scatmech_to_spectrum(f);
  EXPECT_LT((back.channels[0] - s.channels[1]).cwiseAbs().maxCoeff(), 1e-14);
  // The written rows evaluated by SCATMECH's definition reproduce the spectrum.
  std::vector<Row> rows;
  for (const auto& r : f.rows) rows.push_back({r.i, r.j, r.n, r.m, r.k, r.l, r.p, r.a});
  std::uniform_real_distribution<double> th(0.0, M_PI / 2), ph(-M_PI, M_PI);
  for (int t = 0; t < 200; ++t) {
    const double ti = th(g), ts = th(g), ps = ph(g);
    double mag = 0;
    const double want = scatmech_f11(rows, 1.0, 1.0, ti, ts, ps, mag);
    Spectrum one = s;
    one.channels = {s.channels[1]};
    EXPECT_NEAR(ours(one, ti, ts, ps), want, kEvalTol * mag);
  }
}

TEST(ScatmechCoefficients, ExportRefusesWhatScatmechCannotHold) {
  const int order = 2;
  Spectrum s;
  s.order = order;
  s.source = "test";
  Eigen::MatrixXd c = Eigen::MatrixXd::Random(6, 6);
  s.channels = {c + c.transpose()};  // a general (anisotropic) reciprocal spectrum
  EXPECT_THROW(format_scatmech_coefficients(s, 0, false), UnsupportedError);
  const ScatmechExport e = format_scatmech_coefficients(s, 0, true);
  EXPECT_NEAR(e.anisotropic_fraction, anisotropic_energy_fraction(s.channels[0]), 1e-15);
  EXPECT_NE(e.text.find("; isotropic projection: energy fraction"), std::string::npos);
  s.cosine = true;
  EXPECT_THROW(format_scatmech_coefficients(s, 0, true), UnsupportedError);
  s.cosine = false;
  EXPECT_THROW(format_scatmech_coefficients(s, 1, true), ArgumentError);
}

// A spectrum stored isotropic (`fit --isotropic`) is exported without --isotropic: isotropic_part does not
// symmetrize, so such a spectrum of non-reciprocal data keeps an antisymmetric part outside the isotropic modes;
// the export drops it (reported) instead of refusing a tiny "anisotropic" fraction.
TEST(ScatmechCoefficients, SpectrumStoredIsotropicIsExportedWithoutTheFlag) {
  constexpr double kRoundingTol = 1e-13;  // sums of a few dozen O(1) products
  const int order = 4;
  Spectrum s;
  s.order = order;
  s.source = "test";
  s.isotropic = true;
  const int m = hemisphere_basis_count(order);
  const Eigen::MatrixXd c = isotropic_part(Eigen::MatrixXd::Random(m, m), order);  // not symmetric
  s.channels = {c};
  const ScatmechExport e = format_scatmech_coefficients(s, 0, false);
  EXPECT_GT(e.anisotropic_fraction, kScatmechIsotropyTolerance);
  // What is written is the symmetric part (C + C^T) / 2, which for an isotropic C lies in the isotropic modes.
  const Eigen::MatrixXd back = coefficients_from_ibsss(order, e.coefficients);
  EXPECT_LT((back - (c + c.transpose()) / 2).cwiseAbs().maxCoeff(), kRoundingTol);
  EXPECT_NE(e.text.find("of a spectrum stored isotropic"), std::string::npos);
  s.isotropic = false;  // the same C not flagged isotropic still needs --isotropic
  EXPECT_THROW(format_scatmech_coefficients(s, 0, false), UnsupportedError);
}

TEST(ScatmechCoefficients, BadFilesAreLineNumbered) {
  ScratchDir d;
  auto check = [&](const std::string& name, const std::string& content, const std::string& expect) {
    test::write_bytes(d / name, content);
    try {
      read_scatmech_coefficients(d / name);
      ADD_FAILURE() << "no error for " << name;
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find(expect), std::string::npos) << m << "\n  lacks: " << expect;
      EXPECT_EQ(m.rfind(d / name, 0), 0u);
      EXPECT_EQ(m.find('\n'), std::string::npos);
    }
  };
  check("empty.csv", "", "no coefficient of the unpolarized element (i = j = 1)");
  check("few.csv", "1,1,0,0,0,0,0\n", ":1: expected 8 fields (i,j,n,m,k,l,p,a), found 7");
  check("real.csv", "; c\n1,1,2.5,0,0,0,0,1\n", ":2: column 'n' expected an integer, found '2.5'");
  check("a.csv", "1,1,0,0,0,0,0,x\n", ":1: column 'a' expected a number, found 'x'");
  check("inf.csv", "1,1,0,0,0,0,0,inf\n", ":1: column 'a' expected a finite number");
  check("ij.csv", "1,1,0,0,0,0,0,1\n2,1,0,0,0,0,0,1\n", ":2: Mueller indices expected i <= j");
  check("i5.csv", "1,5,0,0,0,0,0,1\n", ":1: Mueller indices i, j expected in 1..4, found 1, 5");
  check("p.csv", "1,1,0,0,0,0,5,1\n", ":1: wavelength power p expected in 0..4, found 5");
  check("lbig.csv", "1,1,4,2,4,4,0,1\n", "needs |l| <= min(n, m) with n - l and m - l even, found n = 4, m = 2, l = 4");
  check("parity.csv", "1,1,3,2,1,1,0,1\n", "found n = 3, m = 2, l = 1");
  check("neg.csv", "1,1,-2,0,0,0,0,1\n", "radial orders n, m expected in [0, 64], found -2, 0");
  check("head.csv", "i,j,n,m,k,l,q,a\n1,1,0,0,0,0,0,1\n", ":1: expected the header 'i,j,n,m,k,l,p,a'");
  check("pol.csv", "1,2,0,0,0,0,0,1\n", "no coefficient of the unpolarized element (i = j = 1), expected at least one (1 rows");
  // Blank-separated fields, CRLF and a BOM are fine.
  test::write_bytes(d / "ws.csv", "\xEF\xBB\xBF 1 1 0 0 0 0 0 2 \r\n\r\n");
  EXPECT_NEAR(scatmech_to_spectrum(read_scatmech_coefficients(d / "ws.csv")).channels[0](0, 0), 2.0, 0);
  // Wavelength terms need the wavelength.
  test::write_bytes(d / "lam.csv", "1,1,0,0,0,0,1,2\n");
  EXPECT_THROW(scatmech_to_spectrum(read_scatmech_coefficients(d / "lam.csv")), ArgumentError);
}

TEST(ScatmechExportFigures, TheChannelIsAskedForOnlyWhenThereAreSeveral) {
  Spectrum one, three;
  one.order = three.order = 0;
  one.channels.assign(1, Eigen::MatrixXd::Zero(1, 1));
  three.channels.assign(3, Eigen::MatrixXd::Zero(1, 1));
  EXPECT_EQ(scatmech_export_channel(one, -1, "one.h5"), 0);
  EXPECT_EQ(scatmech_export_channel(three, 2, "three.h5"), 2);
  try {
    scatmech_export_channel(three, -1, "three.h5");
    FAIL() << "a channel of three was chosen silently";
  } catch (const ArgumentError& e) {
    EXPECT_STREQ(e.what(), "export: three.h5 has 3 channels; choose one with --channel (0..2)");
  }
}

TEST(ScatmechExportFigures, TheTextSaysWhenTheAnisotropicPartWasDropped) {
  ScatmechExport kept, dropped;
  kept.rows = dropped.rows = 45;
  dropped.anisotropic_fraction = 0.25;
  EXPECT_EQ(scatmech_export_text(kept, 8, 0, "a.h5", "a.csv"),
            "a.h5 -> a.csv (SCATMECH coefficients)\n  order 8, channel 0, 45 rows, anisotropic energy fraction 0\n");
  EXPECT_NE(scatmech_export_text(dropped, 8, 1, "a.h5", "a.csv").find("fraction 0.25 (dropped: isotropic projection)\n"), std::string::npos);
  ScatmechPolynomialExport p;
  p.rows = 135;
  p.misfit = 0.0125;
  EXPECT_EQ(scatmech_polynomial_export_text(p, 8, 3, 2, "s.h5", "s.csv"),
            "s.h5 -> s.csv (SCATMECH coefficients, polynomial in wavelength)\n"
            "  order 8, 3 wavelength(s), degree 2, 135 rows, relative misfit 0.0125, anisotropic energy fraction 0\n");
}

}  // namespace
}  // namespace icobrdf
