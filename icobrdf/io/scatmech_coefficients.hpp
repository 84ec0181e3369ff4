#pragma once
// Coefficient files of NIST SCATMECH's ZernikeExpansion_BRDF_Model (T. A. Germer's extension of
// Koenderink & van Doorn 1998 to the Mueller matrix): import as an isotropic Spectrum, and export.
//
// File: one coefficient per line, eight fields separated by commas and/or blanks:
//   i, j, n, m, k, l, p, a
// i, j: Mueller element (1-based, i <= j, 1..4); n, m: radial orders; k, l: azimuthal orders; p: power of
// the wavelength lambda [um]; a: the coefficient. SCATMECH skips text from ';' to the end of a line. Only
// the unpolarized element i = j = 1 determines the (unpolarized) BRDF; rows of other elements are
// validated, counted and ignored on import. docs/readers.md derives the mapping; in short, SCATMECH
// evaluates (as its source code does; angles as in its BRDF_Model: theta_i of the vector to the source,
// theta_s and phi_s of the scattered vector, phi_s = 0 the forward half of the plane of incidence, sample
// rotation 0):
//   f_11 = r(lambda) sum_rows a lambda^p I^S_{n m l},
//   I^S_{nml} = (1/2pi) sqrt((n+1)(m+1)/A^S_nml) [R_n^l(rho_i) R_m^l(rho_s) + R_m^l(rho_i) R_n^l(rho_s)] cos(l (phi_s - pi)),
//   A^S = 4 if n = 0 or (n = m and l = 0); 2 if n = m or l = 0; 1 otherwise,  rho = sqrt(2) sin(theta/2),
// with the azimuthal order read from column l (the documentation's formula writes k: rows with k != l
// are accepted, follow the code, and are counted). With w_i the direction to the source at azimuth pi,
// w_r = (theta_s, phi_s), I^S_{nml} = sqrt(A_{NM|l|} / A^S_{nml}) I_{NM}^{|l|}(w_i, w_r) with N = max(n, m),
// M = min(n, m) and I, A those of icobrdf/core/basis/isotropic_modes.hpp: the factor is 1 except for n = 0 < m
// (1/sqrt(2)). So the IBSSS coefficient of I_NM^L is the sum over the rows mapping to it of
// a lambda^p r sqrt(A / A^S).
// Strictness (InputError with file:line): fields not 8, non-integer indices, i or j outside 1..4, i > j,
// p outside 0..4 (SCATMECH's own range check), and for the 11 element n or m outside [0, kMaxScatmechOrder],
// |l| > min(n, m) or n - l, m - l odd (R_n^l undefined or the term identically zero).
#include <nlohmann/json.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

#include "icobrdf/core/spectrum/spectrum.hpp"

namespace icobrdf {

inline constexpr int kMaxScatmechOrder = 64;

struct ScatmechRow {
  int i, j, n, m, k, l, p;
  double a;
  int line;
};

struct ScatmechCoefficients {
  std::string path;
  std::vector<ScatmechRow> rows;  // every data row, in file order
  long long unpolarized_rows = 0; // i = j = 1
  long long polarized_rows = 0;   // other elements (ignored for the unpolarized BRDF)
  long long k_differs_rows = 0;   // 11 rows with k != l (azimuthal order taken from l, as SCATMECH's code)
  int order = 0;                  // max(n, m) over the 11 rows
  bool wavelength_dependent = false;  // some 11 row has p != 0
};

// Parses and validates a coefficient file (UTF-8 BOM, CRLF, ';' and '#' comments, blank lines and an
// optional header row "i,j,n,m,k,l,p,a" are accepted). InputError when there is no 11 row.
ScatmechCoefficients read_scatmech_coefficients(const std::string& path);

// Content test used to dispatch a SOURCE (icobrdf/io/measured_sources.hpp): true when the first content line of the
// first kScatmechSniffBytes bytes (after a BOM, blank lines and ';' / '#' comments) is the header
// "i,j,n,m,k,l,p,a" (any case) or a row of eight fields, seven integers and a number. BRDF sample CSVs
// (header theta_i,...) and binary files give false. A file that cannot be opened gives false.
inline constexpr long kScatmechSniffBytes = 65536;
bool looks_like_scatmech_coefficients(const std::string& path);

struct ScatmechImportOptions {
  double wavelength_um = -1.0;  // lambda [um]; required (> 0) when the file has p != 0 rows
  double scale = 1.0;           // SCATMECH's `scale` parameter r(lambda) (finite, >= 0)
};

// Wavelength dependence (the p column): f = r sum_p lambda^p sum_modes b_p I_NM^L, lambda in micrometres.
// The coefficients of each power, exact (the rows of power p summed as scatmech_to_spectrum sums them), so that
// a file's polynomial can be evaluated at any wavelength, refitted, and written back.
inline constexpr int kMaxScatmechPower = 4;  // SCATMECH's own range check on p
// What `export --format scatmech` says of a material with a half-angle lobe (icobrdf/io/spectrum_file.hpp
// read_spectrum_file): the format holds modes alone, so the material is refused rather than cut to its modes.
inline constexpr const char* kScatmechModesOnly =
    "the SCATMECH format stores Zernike modes only; export it with --format rgl or merl, or refit it with representations = [\"modes\"]";
struct ScatmechWavelengthPolynomial {
  int order = 0;                       // total order N of the isotropic modes
  std::vector<Eigen::VectorXd> ibsss;  // ibsss[p]: IBSSS coefficients (Table 2 order) of lambda^p [1/sr um^-p]
  // sum_p lambda^p ibsss[p]: the IBSSS vector at lambda [um].
  Eigen::VectorXd at(double lambda_um) const;
};
// InputError as scatmech_to_spectrum for sums that overflow; ArgumentError for a bad scale.
ScatmechWavelengthPolynomial scatmech_wavelength_polynomial(const ScatmechCoefficients& file, double scale = 1.0);

// Least-squares polynomial of `degree` (0..kMaxScatmechPower) in lambda [um] through the IBSSS vectors of
// isotropic spectra of `order` at the given wavelengths, coefficient by coefficient (column-pivoted QR of the
// Vandermonde matrix; exact interpolation when there are degree + 1 wavelengths). ArgumentError for fewer
// wavelengths than degree + 1, repeated ones, wavelengths <= 0 or vectors of another length.
ScatmechWavelengthPolynomial fit_wavelength_polynomial(const std::vector<double>& lambdas_um, const std::vector<Eigen::VectorXd>& ibsss,
                                                       int order, int degree);

// Rows "1,1,N,M,L,L,p,a" for p = 0..P and every isotropic mode (Table 2 order within each p), ';' comment
// lines first, 17 significant digits, LF line ends: read back by read_scatmech_coefficients +
// scatmech_wavelength_polynomial to the last bits (the basis factor is 1 for n >= m). UnsupportedError
// (icobrdf/core/support/finite_values.hpp require_finite) for a non-finite coefficient.
std::string format_scatmech_polynomial(const ScatmechWavelengthPolynomial& polynomial, const std::string& source);

// sqrt(A_{max(n,m) min(n,m) |l|} / A^S_{nml}): the factor from SCATMECH's basis function to ours.
double scatmech_basis_factor(int n, int m, int l);

// The isotropic spectrum (one channel, f not g, order = file order) of the 11 element.
// ArgumentError when a wavelength is needed and missing, or options are invalid.
Spectrum scatmech_to_spectrum(const ScatmechCoefficients& file, const ScatmechImportOptions& options = {});

struct ScatmechExport {
  std::string text;                 // the file content
  long long rows = 0;               // coefficient rows written
  double anisotropic_fraction = 0;  // energy of C outside the isotropic modes (dropped when projecting)
  Eigen::VectorXd coefficients;     // the values of column a, in row order
};

// Rows "1,1,N,M,L,L,0,a" (N >= M >= L, one per isotropic mode, Table 2 order) preceded by ';' comment lines,
// numbers with 17 significant digits, LF line ends: readable by SCATMECH as is. `channel` selects the channel
// of a 3-channel spectrum. UnsupportedError for a spectrum of g = f cos(theta_i) (SCATMECH expands f) and,
// unless `project_isotropic` or the spectrum is stored isotropic (its `isotropic` flag: fitted so), for a
// spectrum whose anisotropic energy fraction exceeds kScatmechIsotropyTolerance (SCATMECH's unpolarized
// element is isotropic by construction); the projection is written and the dropped fraction reported.
ScatmechExport format_scatmech_coefficients(const Spectrum& spectrum, int channel, bool project_isotropic);
// Relative anisotropic energy treated as rounding: C built from isotropic modes has ~1e-32.
inline constexpr double kScatmechIsotropyTolerance = 1e-20;

// format_scatmech_coefficients written atomically to `path`, after require_finite (icobrdf/core/support/finite_values.hpp) of
// the coefficients and the anisotropic energy fraction: a spectrum whose conversion overflows (coefficients
// near 1e308) is refused with an UnsupportedError naming `path`, `material` and the step; nothing is written.
ScatmechExport write_scatmech_coefficients(const std::string& path, const Spectrum& spectrum, int channel,
                                           bool project_isotropic, const std::string& material = "");

// Wavelength-dependent export: channel c of `spectrum` is the BRDF at lambdas_um[c]; each channel's
// isotropic coefficients (the rules of format_scatmech_coefficients: f only, anisotropic spectra refused unless
// `project_isotropic`) are fitted by a polynomial of `degree` in lambda (fit_wavelength_polynomial) and
// written atomically as format_scatmech_polynomial. `misfit`: the largest |polynomial - coefficient| over the
// wavelengths, relative to the largest |coefficient| (0 to rounding when degree + 1 = channels).
struct ScatmechPolynomialExport {
  ScatmechWavelengthPolynomial polynomial;
  long long rows = 0;
  double anisotropic_fraction = 0;  // largest over the channels (dropped when projecting)
  double misfit = 0;
};
ScatmechPolynomialExport write_scatmech_polynomial(const std::string& path, const Spectrum& spectrum, const std::vector<double>& lambdas_um,
                                                   int degree, bool project_isotropic, const std::string& material = "");
// The wavelengths [um] of channels named like "550nm" (RGL spectral fits name theirs so); ArgumentError naming
// `what` when a channel has no such name.
std::vector<double> channel_wavelengths_um(const Spectrum& spectrum, const std::string& what);

// The figures of an export as `icobrdf export --json` reports them: order, channel, rows,
// anisotropic_fraction, and projected (the anisotropic part was dropped: anisotropic_fraction above
// kScatmechIsotropyTolerance).
nlohmann::json scatmech_export_json(const ScatmechExport& e, int order, int channel);
// The same of a polynomial export: order, wavelengths_um, degree, rows, misfit, anisotropic_fraction, projected.
nlohmann::json scatmech_polynomial_export_json(const ScatmechPolynomialExport& e, int order, const std::vector<double>& lambdas_um,
                                               int degree);
// The same as `icobrdf export` prints them, two lines: "<input> -> <output> (SCATMECH coefficients)" and
// "  order 8, channel 0, 45 rows, anisotropic energy fraction 0.0123" (+ " (dropped: isotropic projection)").
std::string scatmech_export_text(const ScatmechExport& e, int order, int channel, const std::string& input, const std::string& output);
// Of a polynomial export: "  order 8, 3 wavelength(s), degree 2, 135 rows, relative misfit 0.01, anisotropic ...".
std::string scatmech_polynomial_export_text(const ScatmechPolynomialExport& e, int order, std::size_t wavelengths, int degree,
                                            const std::string& input, const std::string& output);
// The channel an export of `spectrum` (named `input`) writes: `asked` when >= 0, else 0 of a one-channel
// spectrum; ArgumentError "export: <input> has 3 channels; choose one with --channel (0..2)" otherwise.
int scatmech_export_channel(const Spectrum& spectrum, int asked, const std::string& input);

}  // namespace icobrdf
