#include "icobrdf/io/scatmech_coefficients.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>

#include "icobrdf/core/error.hpp"
#include "icobrdf/core/finite_values.hpp"
#include "icobrdf/core/isotropic_modes.hpp"
#include "icobrdf/io/atomic_write.hpp"

namespace icobrdf {

namespace {

const char* const kColumns[8] = {"i", "j", "n", "m", "k", "l", "p", "a"};

std::string where(const std::string& path, int line) { return path + ":" + std::to_string(line); }

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
// (icobrdf/core/isotropic_modes.hpp): n >= m >= l >= 0.
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
          throw InputError(where(path, lineno) + ": expected the header 'i,j,n,m,k,l,p,a' or a coefficient row, found '" +
                           line + "'");
        continue;
      }
    }
    if (fl.size() != 8)
      throw InputError(where(path, lineno) + ": expected 8 fields (i,j,n,m,k,l,p,a), found " + std::to_string(fl.size()));
    ScatmechRow r{};
    int* ints[7] = {&r.i, &r.j, &r.n, &r.m, &r.k, &r.l, &r.p};
    for (int k = 0; k < 7; ++k)
      if (!parse_int(fl[static_cast<size_t>(k)], *ints[k]))
        throw InputError(where(path, lineno) + ": column '" + kColumns[k] + "' expected an integer, found '" +
                         fl[static_cast<size_t>(k)] + "'");
    if (!parse_double(fl[7], r.a)) throw InputError(where(path, lineno) + ": column 'a' expected a number, found '" + fl[7] + "'");
    if (!std::isfinite(r.a)) throw InputError(where(path, lineno) + ": column 'a' expected a finite number, found '" + fl[7] + "'");
    r.line = lineno;
    if (r.i < 1 || r.i > 4 || r.j < 1 || r.j > 4)
      throw InputError(where(path, lineno) + ": Mueller indices i, j expected in 1..4, found " + std::to_string(r.i) + ", " +
                       std::to_string(r.j));
    if (r.i > r.j)
      throw InputError(where(path, lineno) + ": Mueller indices expected i <= j (SCATMECH derives M_ji from M_ij), found i = " +
                       std::to_string(r.i) + ", j = " + std::to_string(r.j));
    if (r.p < 0 || r.p > 4)
      throw InputError(where(path, lineno) + ": wavelength power p expected in 0..4, found " + std::to_string(r.p));
    if (r.i == 1 && r.j == 1) {
      if (r.n < 0 || r.m < 0 || r.n > kMaxScatmechOrder || r.m > kMaxScatmechOrder)
        throw InputError(where(path, lineno) + ": radial orders n, m expected in [0, " + std::to_string(kMaxScatmechOrder) +
                         "], found " + std::to_string(r.n) + ", " + std::to_string(r.m));
      const int L = std::abs(r.l);
      if (L > std::min(r.n, r.m) || (r.n - L) % 2 != 0 || (r.m - L) % 2 != 0)
        throw InputError(where(path, lineno) + ": unpolarized term needs |l| <= min(n, m) with n - l and m - l even, found n = " +
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

Spectrum scatmech_to_spectrum(const ScatmechCoefficients& file, const ScatmechImportOptions& o) {
  if (!std::isfinite(o.scale) || o.scale < 0)
    throw ArgumentError("SCATMECH import: scale r(lambda) must be finite and >= 0, got " + g17(o.scale));
  const bool have_lambda = o.wavelength_um > 0 && std::isfinite(o.wavelength_um);
  if (file.wavelength_dependent && !have_lambda)
    throw ArgumentError(file.path + ": coefficients with wavelength powers p != 0 need the wavelength: add #lambda=UM " +
                        "(micrometres) to the SOURCE");
  const int order = file.order;
  Eigen::VectorXd b = Eigen::VectorXd::Zero(isotropic_mode_count(order));
  for (const auto& r : file.rows) {
    if (r.i != 1 || r.j != 1) continue;
    const double power = r.p == 0 ? 1.0 : std::pow(o.wavelength_um, r.p);
    const int L = std::abs(r.l);
    b[isotropic_mode_index(std::max(r.n, r.m), std::min(r.n, r.m), L)] += r.a * power * o.scale * scatmech_basis_factor(r.n, r.m, r.l);
  }
  // Finite coefficients can still sum (or scale with lambda^p) beyond the double range.
  for (Eigen::Index k = 0; k < b.size(); ++k)
    if (!std::isfinite(b[k])) {
      const auto md = isotropic_modes(order)[static_cast<size_t>(k)];
      throw InputError(file.path + ": the rows of mode (N, M, L) = (" + std::to_string(md.n) + ", " + std::to_string(md.m) +
                       ", " + std::to_string(md.l) + ") sum to " + g17(b[k]) + ", expected a finite coefficient");
    }
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

ScatmechExport format_scatmech_coefficients(const Spectrum& s, int channel, bool project_isotropic) {
  if (s.cosine)
    throw UnsupportedError("SCATMECH export: the spectrum holds g = f cos(theta_i), SCATMECH expands f; refit without --cosine");
  if (channel < 0 || channel >= s.channel_count())
    throw ArgumentError("SCATMECH export: channel " + std::to_string(channel) + " out of range, the spectrum has " +
                        std::to_string(s.channel_count()) + " channel(s)");
  const Eigen::MatrixXd& c = s.channels[static_cast<size_t>(channel)];
  ScatmechExport out;
  out.anisotropic_fraction = anisotropic_energy_fraction(c);
  if (out.anisotropic_fraction > kScatmechIsotropyTolerance && !project_isotropic)
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
    os << "; isotropic projection: anisotropic energy fraction " << g17(out.anisotropic_fraction) << " dropped\n";
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
  atomic_write(path, [&](const std::string& tmp) {
    std::ofstream o(tmp, std::ios::binary | std::ios::trunc);
    o << e.text;
    o.flush();
    if (!o) throw IoError(tmp + ": write failed (coefficient file for " + path + ")");
  });
  return e;
}

}  // namespace icobrdf
