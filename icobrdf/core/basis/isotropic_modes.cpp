#include "icobrdf/core/basis/isotropic_modes.hpp"

#include <cmath>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/zernike.hpp"

namespace icobrdf {

namespace {

// One entry of the coefficient matrix E_k of an isotropic mode.
struct Entry {
  int a, b;
  double w;
};

void check_isotropic_order(int order, const char* where) {
  if (order < 0 || order > kMaxZernikeOrder)
    throw ArgumentError(std::string(where) + ": order must be in [0, " + std::to_string(kMaxZernikeOrder) +
                        "], got " + std::to_string(order));
}

void check_mode(int n, int m, int l, const char* where) {
  if (!(n >= m && m >= l && l >= 0) || (n - l) % 2 != 0 || (m - l) % 2 != 0 || n > kMaxZernikeOrder)
    throw ArgumentError(std::string(where) + ": need 128 >= n >= m >= l >= 0 with n-l, m-l even, got (n, m, l) = (" +
                        std::to_string(n) + ", " + std::to_string(m) + ", " + std::to_string(l) + ")");
}

// The nonzero entries of E_k (see the header): up to four entries of a symmetric matrix of unit norm.
int entries(const IsotropicMode& k, Entry* out) {
  if (k.l == 0) {
    const int a = ansi_index(k.n, 0), b = ansi_index(k.m, 0);
    if (a == b) {
      out[0] = {a, a, 1.0};
      return 1;
    }
    out[0] = {a, b, M_SQRT1_2};
    out[1] = {b, a, M_SQRT1_2};
    return 2;
  }
  const int ap = ansi_index(k.n, k.l), am = ansi_index(k.n, -k.l);
  const int bp = ansi_index(k.m, k.l), bm = ansi_index(k.m, -k.l);
  if (k.n == k.m) {
    out[0] = {ap, ap, M_SQRT1_2};
    out[1] = {am, am, M_SQRT1_2};
    return 2;
  }
  out[0] = {ap, bp, 0.5};
  out[1] = {bp, ap, 0.5};
  out[2] = {am, bm, 0.5};
  out[3] = {bm, am, 0.5};
  return 4;
}

// Count of modes with this n: sum over m = n mod 2, ..., n (step 2) of floor(m/2) + 1.
int modes_with_n(int n) {
  int c = 0;
  for (int m = n % 2; m <= n; m += 2) c += m / 2 + 1;
  return c;
}

}  // namespace

int isotropic_mode_count(int order) {
  check_isotropic_order(order, "isotropic_mode_count");
  int c = 0;
  for (int n = 0; n <= order; ++n) c += modes_with_n(n);
  return c;
}

std::vector<IsotropicMode> isotropic_modes(int order) {
  check_isotropic_order(order, "isotropic_modes");
  std::vector<IsotropicMode> modes;
  for (int n = 0; n <= order; ++n)
    for (int m = n % 2; m <= n; m += 2)
      for (int l = m % 2; l <= m; l += 2) modes.push_back({n, m, l});
  return modes;
}

int isotropic_mode_index(int n, int m, int l) {
  check_mode(n, m, l, "isotropic_mode_index");
  int idx = n > 0 ? isotropic_mode_count(n - 1) : 0;
  for (int mm = n % 2; mm < m; mm += 2) idx += mm / 2 + 1;
  return idx + (l - m % 2) / 2;
}

std::vector<HelmholtzComponent> isotropic_mode_components(int n, int m, int l) {
  check_mode(n, m, l, "isotropic_mode_components");
  if (l == 0) return {{helmholtz_mode_index(ansi_index(n, 0), ansi_index(m, 0)), 1.0}};
  return {{helmholtz_mode_index(ansi_index(n, l), ansi_index(m, l)), M_SQRT1_2},
          {helmholtz_mode_index(ansi_index(n, -l), ansi_index(m, -l)), M_SQRT1_2}};
}

Eigen::VectorXd ibsss_from_coefficients(const Eigen::MatrixXd& c) {
  if (c.rows() != c.cols())
    throw ArgumentError("IBSSS from coefficients: C must be square, got " + std::to_string(c.rows()) + " x " +
                        std::to_string(c.cols()));
  const auto modes = isotropic_modes(hemisphere_basis_order(static_cast<int>(c.rows())));
  Eigen::VectorXd v(static_cast<Eigen::Index>(modes.size()));
  Entry e[4];
  for (size_t k = 0; k < modes.size(); ++k) {
    const int cnt = entries(modes[k], e);
    double s = 0.0;
    for (int t = 0; t < cnt; ++t) s += e[t].w * c(e[t].a, e[t].b);
    v[static_cast<Eigen::Index>(k)] = s;
  }
  return v;
}

Eigen::MatrixXd coefficients_from_ibsss(int order, const Eigen::VectorXd& ibsss) {
  const auto modes = isotropic_modes(order);
  if (ibsss.size() != static_cast<Eigen::Index>(modes.size()))
    throw ArgumentError("coefficients from IBSSS: order " + std::to_string(order) + " has " +
                        std::to_string(modes.size()) + " isotropic modes, got a vector of length " +
                        std::to_string(ibsss.size()));
  const int m = hemisphere_basis_count(order);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(m, m);
  Entry e[4];
  for (size_t k = 0; k < modes.size(); ++k) {
    const int cnt = entries(modes[k], e);
    for (int t = 0; t < cnt; ++t) c(e[t].a, e[t].b) += e[t].w * ibsss[static_cast<Eigen::Index>(k)];
  }
  return c;
}

Eigen::MatrixXd isotropic_projection(const Eigen::MatrixXd& c) {
  const int order = hemisphere_basis_order(static_cast<int>(c.rows()));
  return coefficients_from_ibsss(order, ibsss_from_coefficients(c));
}

double anisotropic_energy_fraction(const Eigen::MatrixXd& c) {
  // The fraction does not depend on the scale of C: divided by max|C| first, so that the squares of finite
  // coefficients near 1e308 cannot overflow (Inf / Inf would give NaN).
  const double largest = c.size() ? c.cwiseAbs().maxCoeff() : 0.0;
  if (largest == 0.0) return 0.0;
  const Eigen::MatrixXd u = c / largest;
  return (u - isotropic_projection(u)).squaredNorm() / u.squaredNorm();
}

Eigen::MatrixXd isotropic_modes_eval(int order, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  if (wi.rows() != wr.rows())
    throw ArgumentError("isotropic modes: wi has " + std::to_string(wi.rows()) + " rows but wr has " +
                        std::to_string(wr.rows()));
  const auto modes = isotropic_modes(order);
  const Eigen::MatrixXd ki = hemisphere_basis_matrix(order, wi);  // rows x M
  const Eigen::MatrixXd kr = hemisphere_basis_matrix(order, wr);
  Eigen::MatrixXd out(wi.rows(), static_cast<Eigen::Index>(modes.size()));
  const auto count = static_cast<Eigen::Index>(modes.size());
#pragma omp parallel for schedule(static) if (wi.rows() * count > 200000)
  for (Eigen::Index k = 0; k < count; ++k) {
    Entry e[4];
    const int cnt = entries(modes[static_cast<size_t>(k)], e);
    out.col(k) = e[0].w * ki.col(e[0].a).cwiseProduct(kr.col(e[0].b));
    for (int t = 1; t < cnt; ++t) out.col(k) += e[t].w * ki.col(e[t].a).cwiseProduct(kr.col(e[t].b));
  }
  return out;
}

}  // namespace icobrdf
