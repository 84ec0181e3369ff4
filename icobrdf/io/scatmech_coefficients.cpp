#include "icobrdf/io/scatmech_coefficients.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include <Eigen/QR>
#include <fmt/core.h>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/finite_values.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/io/atomic_write.hpp"

namespace icobrdf {

namespace {

const char* const kColumns[8] = {"i", "j", "n", "m", "k", "l", "p", "a"};

std::string line_where(const std::string& path, int line) { return path + ":" + std::to_string(line); }

std::vector<std::string> split_fields(const std::string& s) {  // blank-separated
  std::vector<std::string> out;
  std::istringstream is(s);
  std::string f;
  while (is >> f) out.push_back(f);
  return out;
}

// Comma-separated fields (trimmed) when the line has a comma, else blank-separated fields.
std::vector<std::string> fields_of(const std::string& line) {
  if (line.find(',') == std::string::npos) return split_fields(line);
  std::vector<std::string> out;
  std::string cur;
  auto flush = [&] {
    const auto b = cur.find_first_not_of(" \t"), e = cur.find_last_not_of(" \t");
    out.push_back(b == std::string::npos ? std::string() : cur.substr(b, e - b + 1));
    cur.clear();
  };
  for (char c : line) {
    if (c == ',') flush();
    else cur += c;
  }
  flush();
  return out;
}

bool parse_int(const std::string& f, int& v) {
  if (f.empty()) return false;
  errno = 0;
  char* end = nullptr;
  const long x = std::strtol(f.c_str(), &end, 10);
  if (errno || *end != '\0' || x < -100000 || x > 100000) return false;
  v = static_cast<int>(x);
  return true;
}

bool parse_double(const std::string& f, double& v) {
  if (f.empty()) return false;
  char* end = nullptr;
  v = std::strtod(f.c_str(), &end);
  return *end == '\0';
}

// The divisor A_nml in the normalization of the isotropic mode I_nm^l as this program defines it
// (icobrdf/core/basis/isotropic_modes.hpp): n >= m >= l >= 0.
int isotropic_norm_divisor(int n, int m, int l) {
  if (n == m && l == 0) return 4;
  if (n == m || l == 0) return 2;
  return 1;
}

// The divisor A^S_nml of SCATMECH's basis function as SCATMECH evaluates it (n = its column 3): unlike A,
// it is 4 whenever its n is 0.
int scatmech_norm_divisor(int n, int m, int l) {
  if (n == 0 || (n == m && l == 0)) return 4;
  if (n == m || l == 0) return 2;
  return 1;
}

std::string g17(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

}  // namespace

double scatmech_basis_factor(int n, int m, int l) {
  const int L = std::abs(l);
  return std::sqrt(static_cast<double>(isotropic_norm_divisor(std::max(n, m), std::min(n, m), L)) / scatmech_norm_divisor(n, m, l));
}

bool looks_like_scatmech_coefficients(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string head(static_cast<size_t>(kScatmechSniffBytes), '\0');
  in.read(&head[0], kScatmechSniffBytes);
  head.resize(static_cast<size_t>(in.gcount()));
  if (head.compare(0, 3, "\xEF\xBB\xBF") == 0) head.erase(0, 3);
  std::istringstream lines(head);
  std::string line;
  while (std::getline(lines, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto cpos = line.find_first_of(";#");
    if (cpos != std::string::npos) line.erase(cpos);
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    const std::vector<std::string> fl = fields_of(line);
    if (fl.size() != 8) return false;
    bool header = true, row = true;
    for (size_t k = 0; k < 8; ++k) {
      std::string lower = fl[k];
      for (auto& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      header = header && lower == kColumns[k];
      int v;
      double a;
      row = row && (k < 7 ? parse_int(fl[k], v) : parse_double(fl[k], a));
    }
    return header || row;
  }
  return false;
}

ScatmechCoefficients read_scatmech_coefficients(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open coefficient file for reading");
  ScatmechCoefficients f;
  f.path = path;
  std::string line;
  int lineno = 0;
  bool first_content = true;
  while (std::getline(in, line)) {
    ++lineno;
    if (lineno == 1 && line.size() >= 3 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const auto cpos = line.find_first_of(";#");
    if (cpos != std::string::npos) line.erase(cpos);
    if (line.find_first_not_of(" \t") == std::string::npos) continue;
    std::vector<std::string> fl = fields_of(line);
    if (first_content) {
      first_content = false;
      if (!fl.empty() && !fl[0].empty() && std::isalpha(static_cast<unsigned char>(fl[0][0]))) {
        bool ok = fl.size() == 8;
        for (size_t k = 0; ok && k < 8; ++k) {
          std::string lower = fl[k];
          for (auto& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
          ok = lower == kColumns[k];
        }
        if (!ok)
          throw InputError(line_where(path, lineno) + ": expected the header 'i,j,n,m,k,l,p,a' or a coefficient row, found '" +
                           line + "'");
        continue;
      }
    }
    if (fl.size() != 8)
      throw InputError(line_where(path, lineno) + ": expected 8 fields (i,j,n,m,k,l,p,a), found " + std::to_string(fl.size()));
    ScatmechRow r{};
    int* ints[7] = {&r.i, &r.j, &r.n, &r.m, &r.k, &r.l, &r.p};
    for (int k = 0; k < 7; ++k)
      if (!parse_int(fl[static_cast<size_t>(k)], *ints[k]))
        throw InputError(line_where(path, lineno) + ": column '" + kColumns[k] + "' expected an integer, found '" +
                         fl[static_cast<size_t>(k)] + "'");
    if (!parse_double(fl[7], r.a)) throw InputError(line_where(path, lineno) + ": column 'a' expected a number, found '" + fl[7] + "'");
    if (!std::isfinite(r.a)) throw InputError(line_where(path, lineno) + ": column 'a' expected a finite number, found '" + fl[7] + "'");
    r.line = lineno;
    if (r.i < 1 || r.i > 4 || r.j < 1 || r.j > 4)
      throw InputError(line_where(path, lineno) + ": Mueller indices i, j expected in 1..4, found " + std::to_string(r.i) + ", " +
                       std::to_string(r.j));
    if (r.i > r.j)
      throw InputError(line_where(path, lineno) + ": Mueller indices expected i <= j (SCATMECH derives M_ji from M_ij), found i = " +
                       std::to_string(r.i) + ", j = " + std::to_string(r.j));
    if (r.p < 0 || r.p > 4)
      throw InputError(line_where(path, lineno) + ": wavelength power p expected in 0..4, found " + std::to_string(r.p));
    if (r.i == 1 && r.j == 1) {
      if (r.n < 0 || r.m < 0 || r.n > kMaxScatmechOrder || r.m > kMaxScatmechOrder)
        throw InputError(line_where(path, lineno) + ": radial orders n, m expected in [0, " + std::to_string(kMaxScatmechOrder) +
                         "], found " + std::to_string(r.n) + ", " + std::to_string(r.m));
      const int L = std::abs(r.l);
      if (L > std::min(r.n, r.m) || (r.n - L) % 2 != 0 || (r.m - L) % 2 != 0)
        throw InputError(line_where(path, lineno) + ": unpolarized term needs |l| <= min(n, m) with n - l and m - l even, found n = " +
                         std::to_string(r.n) + ", m = " + std::to_string(r.m) + ", l = " + std::to_string(r.l));
      ++f.unpolarized_rows;
      if (r.k != r.l) ++f.k_differs_rows;
      if (r.p != 0) f.wavelength_dependent = true;
      f.order = std::max({f.order, r.n, r.m});
    } else {
      ++f.polarized_rows;
    }
    f.rows.push_back(r);
  }
  if (f.unpolarized_rows == 0)
    throw InputError(path + ": no coefficient of the unpolarized element (i = j = 1), expected at least one (" +
                     std::to_string(f.rows.size()) + " rows of other elements)");
  return f;
}

namespace {

// The IBSSS vector of every mode, summed from the rows of power p (scaled, SCATMECH's basis factor applied).
ScatmechWavelengthPolynomial polynomial_of(const ScatmechCoefficients& file, double scale) {
  ScatmechWavelengthPolynomial poly;
  poly.order = file.order;
  for (const auto& r : file.rows) {
    if (r.i != 1 || r.j != 1) continue;
    while (static_cast<int>(poly.ibsss.size()) <= r.p) poly.ibsss.push_back(Eigen::VectorXd::Zero(isotropic_mode_count(file.order)));
    poly.ibsss[static_cast<size_t>(r.p)][isotropic_mode_index(std::max(r.n, r.m), std::min(r.n, r.m), std::abs(r.l))] +=
        r.a * scale * scatmech_basis_factor(r.n, r.m, r.l);
  }
  return poly;
}

// Finite coefficients can still sum (or scale with lambda^p) beyond the double range.
void require_finite_modes(const std::string& path, int order, const Eigen::VectorXd& b) {
  for (Eigen::Index k = 0; k < b.size(); ++k)
    if (!std::isfinite(b[k])) {
      const auto md = isotropic_modes(order)[static_cast<size_t>(k)];
      throw InputError(path + ": the rows of mode (N, M, L) = (" + std::to_string(md.n) + ", " + std::to_string(md.m) +
                       ", " + std::to_string(md.l) + ") sum to " + g17(b[k]) + ", expected a finite coefficient");
    }
}

void require_scale(double scale) {
  if (!std::isfinite(scale) || scale < 0)
    throw ArgumentError("SCATMECH import: scale r(lambda) must be finite and >= 0, got " + g17(scale));
}

}  // namespace

Eigen::VectorXd ScatmechWavelengthPolynomial::at(double lambda_um) const {
  Eigen::VectorXd b = Eigen::VectorXd::Zero(isotropic_mode_count(order));
  for (size_t p = 0; p < ibsss.size(); ++p) b += (p == 0 ? 1.0 : std::pow(lambda_um, static_cast<double>(p))) * ibsss[p];
  return b;
}

ScatmechWavelengthPolynomial scatmech_wavelength_polynomial(const ScatmechCoefficients& file, double scale) {
  require_scale(scale);
  ScatmechWavelengthPolynomial poly = polynomial_of(file, scale);
  for (const auto& b : poly.ibsss) require_finite_modes(file.path, poly.order, b);
  return poly;
}

Spectrum scatmech_to_spectrum(const ScatmechCoefficients& file, const ScatmechImportOptions& o) {
  require_scale(o.scale);
  const bool have_lambda = o.wavelength_um > 0 && std::isfinite(o.wavelength_um);
  if (file.wavelength_dependent && !have_lambda)
    throw ArgumentError(file.path + ": coefficients with wavelength powers p != 0 need the wavelength: add #lambda=UM " +
                        "(micrometres) to the SOURCE");
  const int order = file.order;
  const Eigen::VectorXd b = polynomial_of(file, o.scale).at(have_lambda ? o.wavelength_um : 1.0);
  require_finite_modes(file.path, order, b);
  Spectrum s;
  s.order = order;
  s.isotropic = true;
  s.cosine = false;
  s.channels.push_back(coefficients_from_ibsss(order, b));
  if (!s.channels.back().allFinite())
    throw InputError(file.path + ": the coefficient matrix of the imported spectrum overflows, expected finite coefficients");
  s.source = "scatmech:" + file.path;
  s.anisotropy_fraction = 0.0;
  s.reciprocity_violation = 0.0;
  return s;
}

ScatmechWavelengthPolynomial fit_wavelength_polynomial(const std::vector<double>& lambdas_um, const std::vector<Eigen::VectorXd>& ibsss,
                                                       int order, int degree) {
  if (degree < 0 || degree > kMaxScatmechPower)
    throw ArgumentError("wavelength polynomial: degree expected in 0.." + std::to_string(kMaxScatmechPower) + " (SCATMECH's p range), found " +
                        std::to_string(degree));
  if (lambdas_um.size() != ibsss.size())
    throw ArgumentError("wavelength polynomial: " + std::to_string(lambdas_um.size()) + " wavelengths for " + std::to_string(ibsss.size()) + " spectra");
  if (static_cast<int>(lambdas_um.size()) <= degree)
    throw ArgumentError("wavelength polynomial: degree " + std::to_string(degree) + " needs at least " + std::to_string(degree + 1) +
                        " wavelengths, found " + std::to_string(lambdas_um.size()));
  const auto w = static_cast<Eigen::Index>(lambdas_um.size());
  const Eigen::Index k = isotropic_mode_count(order);
  Eigen::MatrixXd v(w, degree + 1), y(w, k);
  for (Eigen::Index r = 0; r < w; ++r) {
    const double l = lambdas_um[static_cast<size_t>(r)];
    if (!(l > 0) || !std::isfinite(l)) throw ArgumentError("wavelength polynomial: wavelength " + g17(l) + " um, expected > 0");
    if (ibsss[static_cast<size_t>(r)].size() != k)
      throw ArgumentError("wavelength polynomial: spectrum " + std::to_string(r) + " has " + std::to_string(ibsss[static_cast<size_t>(r)].size()) +
                          " isotropic coefficients, expected " + std::to_string(k));
    for (int p = 0; p <= degree; ++p) v(r, p) = p == 0 ? 1.0 : std::pow(l, p);
    y.row(r) = ibsss[static_cast<size_t>(r)].transpose();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(v);
  if (qr.rank() < degree + 1)
    throw ArgumentError("wavelength polynomial: the wavelengths do not determine a polynomial of degree " + std::to_string(degree) +
                        " (repeated wavelengths?)");
  const Eigen::MatrixXd x = qr.solve(y);  // (degree + 1) x k
  ScatmechWavelengthPolynomial poly;
  poly.order = order;
  for (int p = 0; p <= degree; ++p) poly.ibsss.push_back(x.row(p).transpose());
  return poly;
}

std::string format_scatmech_polynomial(const ScatmechWavelengthPolynomial& poly, const std::string& source) {
  const auto modes = isotropic_modes(poly.order);
  std::ostringstream os;
  os << "; SCATMECH ZernikeExpansion_BRDF_Model coefficients written by icobrdf\n"
     << "; source: " << source << ", order " << poly.order << ", f in 1/sr = sum over p of a lambda^p, lambda in micrometres\n"
     << "; columns: i,j,n,m,k,l,p,a (unpolarized element i = j = 1; n >= m, k = l)\n";
  for (size_t p = 0; p < poly.ibsss.size(); ++p) {
    require_finite(poly.ibsss[p], "SCATMECH export of '" + source + "'", "the coefficients of lambda^" + std::to_string(p));
    for (size_t k = 0; k < modes.size(); ++k) {
      const auto& md = modes[k];
      os << "1,1," << md.n << "," << md.m << "," << md.l << "," << md.l << "," << p << "," << g17(poly.ibsss[p][static_cast<Eigen::Index>(k)]) << "\n";
    }
  }
  return os.str();
}

ScatmechExport format_scatmech_coefficients(const Spectrum& s, int channel, bool project_isotropic) {
  if (s.cosine)
    throw UnsupportedError("SCATMECH export: the spectrum holds g = f cos(theta_i), SCATMECH expands f; refit without --cosine");
  if (channel < 0 || channel >= s.channel_count())
    throw ArgumentError("SCATMECH export: channel " + std::to_string(channel) + " out of range, the spectrum has " +
                        std::to_string(s.channel_count()) + " channel(s)");
  const Eigen::MatrixXd& c = s.channels[static_cast<size_t>(channel)];
  ScatmechExport out;
  out.anisotropic_fraction = anisotropic_energy_fraction(c);
  // A spectrum stored isotropic (fitted with --isotropic) is invariant under turns about the normal by
  // construction; what lies outside the span of the isotropic modes I_nm^l is then its part antisymmetric in
  // (w_i, w_r) (isotropic_part does not symmetrize), which the flag asks to drop like any anisotropy.
  if (out.anisotropic_fraction > kScatmechIsotropyTolerance && !project_isotropic && !s.isotropic)
    throw UnsupportedError("SCATMECH export: anisotropic energy fraction " + g17(out.anisotropic_fraction) +
                           " exceeds " + g17(kScatmechIsotropyTolerance) +
                           " (SCATMECH's unpolarized element is isotropic); use --isotropic to export the isotropic projection");
  const Eigen::VectorXd b = ibsss_from_coefficients(c);
  out.coefficients = b;
  const auto modes = isotropic_modes(s.order);
  std::ostringstream os;
  os << "; SCATMECH ZernikeExpansion_BRDF_Model coefficients written by icobrdf\n"
     << "; source: " << s.source << ", channel " << channel << ", order " << s.order << ", f in 1/sr (no wavelength terms)\n";
  if (out.anisotropic_fraction > kScatmechIsotropyTolerance)
    os << "; isotropic projection" << (s.isotropic ? " of a spectrum stored isotropic" : "") << ": energy fraction "
       << g17(out.anisotropic_fraction) << " outside the isotropic modes dropped\n";
  os << "; columns: i,j,n,m,k,l,p,a (unpolarized element i = j = 1; n >= m, k = l)\n";
  for (size_t k = 0; k < modes.size(); ++k) {
    const auto& md = modes[k];
    os << "1,1," << md.n << "," << md.m << "," << md.l << "," << md.l << ",0," << g17(b[static_cast<Eigen::Index>(k)]) << "\n";
    ++out.rows;
  }
  out.text = os.str();
  return out;
}

ScatmechExport write_scatmech_coefficients(const std::string& path, const Spectrum& s, int channel, bool project_isotropic,
                                           const std::string& material) {
  ScatmechExport e = format_scatmech_coefficients(s, channel, project_isotropic);
  const std::string where = path + ": SCATMECH export of material '" + material + "' channel " + std::to_string(channel);
  require_finite(e.anisotropic_fraction, where, "the anisotropic energy fraction of C");
  require_finite(e.coefficients, where, "the conversion of C to SCATMECH coefficients a");
  atomic_write_text(path, e.text);
  return e;
}

std::vector<double> channel_wavelengths_um(const Spectrum& s, const std::string& what) {
  std::vector<double> out;
  for (int c = 0; c < s.channel_count(); ++c) {
    const std::string name = c < static_cast<int>(s.channel_names.size()) ? s.channel_names[static_cast<size_t>(c)] : "";
    char* end = nullptr;
    const double nm = std::strtod(name.c_str(), &end);
    if (name.empty() || end == name.c_str() || std::string(end) != "nm" || !(nm > 0) || !std::isfinite(nm))
      throw ArgumentError(what + ": channel " + std::to_string(c) + " is named '" + name +
                          "', not a wavelength like '550nm'; give the channels' wavelengths with --wavelengths");
    out.push_back(nm / 1000.0);
  }
  return out;
}

ScatmechPolynomialExport write_scatmech_polynomial(const std::string& path, const Spectrum& s, const std::vector<double>& lambdas_um,
                                                   int degree, bool project_isotropic, const std::string& material) {
  const std::string where = path + ": SCATMECH export of material '" + material + "'";
  if (static_cast<int>(lambdas_um.size()) != s.channel_count())
    throw ArgumentError(where + ": " + std::to_string(lambdas_um.size()) + " wavelength(s) for " + std::to_string(s.channel_count()) +
                        " channel(s)");
  ScatmechPolynomialExport out;
  std::vector<Eigen::VectorXd> at;
  for (int c = 0; c < s.channel_count(); ++c) {
    const ScatmechExport e = format_scatmech_coefficients(s, c, project_isotropic);
    require_finite(e.coefficients, where, "the conversion of C to SCATMECH coefficients a");
    out.anisotropic_fraction = std::max(out.anisotropic_fraction, e.anisotropic_fraction);
    at.push_back(e.coefficients);
  }
  out.polynomial = fit_wavelength_polynomial(lambdas_um, at, s.order, degree);
  double scale = 0.0;
  for (size_t k = 0; k < at.size(); ++k) {
    out.misfit = std::max(out.misfit, (out.polynomial.at(lambdas_um[k]) - at[k]).cwiseAbs().maxCoeff());
    scale = std::max(scale, at[k].cwiseAbs().maxCoeff());
  }
  if (scale > 0) out.misfit /= scale;
  const std::string text = format_scatmech_polynomial(out.polynomial, s.source.empty() ? material : s.source);
  out.rows = static_cast<long long>(out.polynomial.ibsss.size()) * isotropic_mode_count(s.order);
  atomic_write_text(path, text);
  return out;
}

nlohmann::json scatmech_export_json(const ScatmechExport& e, int order, int channel) {
  return {{"order", order},
          {"channel", channel},
          {"rows", e.rows},
          {"anisotropic_fraction", e.anisotropic_fraction},
          {"projected", e.anisotropic_fraction > kScatmechIsotropyTolerance}};
}

nlohmann::json scatmech_polynomial_export_json(const ScatmechPolynomialExport& e, int order, const std::vector<double>& lambdas_um,
                                               int degree) {
  return {{"order", order},
          {"wavelengths_um", lambdas_um},
          {"degree", degree},
          {"rows", e.rows},
          {"misfit", e.misfit},
          {"anisotropic_fraction", e.anisotropic_fraction},
          {"projected", e.anisotropic_fraction > kScatmechIsotropyTolerance}};
}

std::string scatmech_export_text(const ScatmechExport& e, int order, int channel, const std::string& input, const std::string& output) {
  return fmt::format("{} -> {} (SCATMECH coefficients)\n", input, output) +
         fmt::format("  order {}, channel {}, {} rows, anisotropic energy fraction {:.3g}{}\n", order, channel, e.rows, e.anisotropic_fraction,
                     e.anisotropic_fraction > kScatmechIsotropyTolerance ? " (dropped: isotropic projection)" : "");
}

std::string scatmech_polynomial_export_text(const ScatmechPolynomialExport& e, int order, std::size_t wavelengths, int degree,
                                            const std::string& input, const std::string& output) {
  return fmt::format("{} -> {} (SCATMECH coefficients, polynomial in wavelength)\n", input, output) +
         fmt::format("  order {}, {} wavelength(s), degree {}, {} rows, relative misfit {:.3g}, anisotropic energy fraction {:.3g}{}\n", order,
                     wavelengths, degree, e.rows, e.misfit, e.anisotropic_fraction,
                     e.anisotropic_fraction > kScatmechIsotropyTolerance ? " (dropped: isotropic projection)" : "");
}

int scatmech_export_channel(const Spectrum& spectrum, int asked, const std::string& input) {
  if (asked >= 0) return asked;
  if (spectrum.channel_count() != 1)
    throw ArgumentError(fmt::format("export: {} has {} channels; choose one with --channel (0..{})", input, spectrum.channel_count(),
                                    spectrum.channel_count() - 1));
  return 0;
}

}  // namespace icobrdf
