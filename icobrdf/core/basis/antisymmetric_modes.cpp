#include "icobrdf/core/basis/antisymmetric_modes.hpp"

#include <cmath>
#include <string>

#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

int square_order(const Eigen::MatrixXd& c, const char* what) {
  if (c.rows() != c.cols())
    throw ArgumentError(std::string(what) + ": C must be square, got " + std::to_string(c.rows()) + " x " + std::to_string(c.cols()));
  return hemisphere_basis_order(static_cast<int>(c.rows()));  // throws unless M is a basis count
}

void require_length(Eigen::Index got, long long expected, int order, const char* what) {
  if (got != expected)
    throw ArgumentError(std::string(what) + ": order " + std::to_string(order) + " has " + std::to_string(expected) +
                        " antisymmetric modes, got a vector of length " + std::to_string(got));
}

// C with every entry whose row index has the larger order n kept (n(a) > n(b)), the others 0.
Eigen::MatrixXd lower_by_order(const Eigen::MatrixXd& c) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(c.rows(), c.cols());
  for (Eigen::Index a = 0; a < c.rows(); ++a)
    for (Eigen::Index b = 0; b < c.cols(); ++b)
      if (ansi_to_nl(static_cast<int>(a)).n > ansi_to_nl(static_cast<int>(b)).n) out(a, b) = c(a, b);
  return out;
}

}  // namespace

long long antisymmetric_mode_count(int order) {
  const long long m = hemisphere_basis_count(order);
  return m * (m - 1) / 2;
}

std::vector<IsotropicMode> isotropic_antisymmetric_modes(int order) {
  std::vector<IsotropicMode> out;
  for (const auto& k : isotropic_modes(order))
    if (k.n > k.m) out.push_back(k);
  return out;
}

int isotropic_antisymmetric_mode_count(int order) { return static_cast<int>(isotropic_antisymmetric_modes(order).size()); }

Eigen::VectorXd antisymmetric_from_coefficients(const Eigen::MatrixXd& c) {
  square_order(c, "antisymmetric modes from coefficients");
  const Eigen::Index m = c.rows();
  Eigen::VectorXd z(m * (m - 1) / 2);
  Eigen::Index k = 0;
  for (Eigen::Index b = 0; b < m; ++b)
    for (Eigen::Index a = 0; a < b; ++a) z[k++] = (c(a, b) - c(b, a)) * M_SQRT1_2;
  return z;
}

Eigen::MatrixXd coefficients_from_antisymmetric(int order, const Eigen::VectorXd& z) {
  require_length(z.size(), antisymmetric_mode_count(order), order, "coefficients from antisymmetric modes");
  const Eigen::Index m = hemisphere_basis_count(order);
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(m, m);
  Eigen::Index k = 0;
  for (Eigen::Index b = 0; b < m; ++b)
    for (Eigen::Index a = 0; a < b; ++a) {
      c(a, b) = z[k] * M_SQRT1_2;
      c(b, a) = -z[k++] * M_SQRT1_2;
    }
  return c;
}

// With L_k the entries of E_k (the isotropic mode's matrix) whose row has the larger order, E_J = L_k - L_k^T and
// E_k = L_k + L_k^T. For D = lower(C) - upper(C)^T (a matrix with lower entries only), <C, E_J> = <D, L_k>
// = <D + D^T, E_k> / 2: the IBSSS coefficient of D + D^T, halved.
Eigen::VectorXd isotropic_antisymmetric_from_coefficients(const Eigen::MatrixXd& c) {
  const int order = square_order(c, "isotropic antisymmetric modes from coefficients");
  const Eigen::MatrixXd d = lower_by_order(c) - lower_by_order(c.transpose());
  const Eigen::VectorXd all = ibsss_from_coefficients(d + d.transpose());
  const auto modes = isotropic_modes(order);
  Eigen::VectorXd j(isotropic_antisymmetric_mode_count(order));
  Eigen::Index k = 0;
  for (size_t i = 0; i < modes.size(); ++i)
    if (modes[i].n > modes[i].m) j[k++] = 0.5 * all[static_cast<Eigen::Index>(i)];
  return j;
}

// sum_k j_k (L_k + L_k^T) from the isotropic modes, then its lower part minus that part's transpose.
Eigen::MatrixXd coefficients_from_isotropic_antisymmetric(int order, const Eigen::VectorXd& j) {
  require_length(j.size(), isotropic_antisymmetric_mode_count(order), order, "coefficients from isotropic antisymmetric modes");
  const auto modes = isotropic_modes(order);
  Eigen::VectorXd all = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(modes.size()));
  Eigen::Index k = 0;
  for (size_t i = 0; i < modes.size(); ++i)
    if (modes[i].n > modes[i].m) all[static_cast<Eigen::Index>(i)] = j[k++];
  const Eigen::MatrixXd l = lower_by_order(coefficients_from_ibsss(order, all));
  return l - l.transpose();
}

double antisymmetric_fraction(const Eigen::MatrixXd& c) {
  const double n = c.norm();
  return n > 0 ? (c - c.transpose()).norm() / (2 * n) : 0.0;
}

}  // namespace icobrdf
