#include "icobrdf/core/basis/helmholtz_modes.hpp"

#include <cmath>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"

namespace icobrdf {

namespace {

// The mode count as a matching order, or ArgumentError.
int order_from_mode_count(Eigen::Index count, const char* where) {
  for (int n = 0; n <= 128; ++n) {
    const long long m = (n + 1) * (n + 2) / 2;
    if (m * (m + 1) / 2 == count) return n;
    if (m * (m + 1) / 2 > count) break;
  }
  throw ArgumentError(std::string(where) + ": length " + std::to_string(count) +
                      " is not M(M+1)/2 for M = (N+1)(N+2)/2, N in [0, 128]");
}

}  // namespace

long long helmholtz_mode_count(int order) {
  const long long m = hemisphere_basis_count(order);
  return m * (m + 1) / 2;
}

long long helmholtz_mode_index(int a, int b) {
  if (a < 0 || b < 0)
    throw ArgumentError("Helmholtz mode index: indices must be >= 0, got " + std::to_string(a) + ", " +
                        std::to_string(b));
  if (a > b) std::swap(a, b);
  return static_cast<long long>(b) * (b + 1) / 2 + a;
}

HelmholtzMode helmholtz_mode_at(long long k) {
  if (k < 0) throw ArgumentError("Helmholtz mode: index must be >= 0, got " + std::to_string(k));
  auto b = static_cast<long long>((std::sqrt(8.0 * static_cast<double>(k) + 1.0) - 1.0) / 2.0);
  while (b * (b + 1) / 2 > k) --b;  // guard the floating-point estimate
  while ((b + 1) * (b + 2) / 2 <= k) ++b;
  const int a = static_cast<int>(k - b * (b + 1) / 2), bi = static_cast<int>(b);
  const BasisIndex ka = ansi_to_nl(a), kb = ansi_to_nl(bi);
  return {a, bi, ka.n, ka.l, kb.n, kb.l};
}

std::vector<HelmholtzMode> helmholtz_modes(int order) {
  const long long count = helmholtz_mode_count(order);
  const int m = hemisphere_basis_count(order);
  std::vector<HelmholtzMode> modes;
  modes.reserve(static_cast<size_t>(count));
  for (int b = 0; b < m; ++b) {
    const BasisIndex kb = ansi_to_nl(b);
    for (int a = 0; a <= b; ++a) {
      const BasisIndex ka = ansi_to_nl(a);
      modes.push_back({a, b, ka.n, ka.l, kb.n, kb.l});
    }
  }
  return modes;
}

Eigen::VectorXd bsss_from_coefficients(const Eigen::MatrixXd& c) {
  if (c.rows() != c.cols())
    throw ArgumentError("BSSS from coefficients: C must be square, got " + std::to_string(c.rows()) + " x " +
                        std::to_string(c.cols()));
  hemisphere_basis_order(static_cast<int>(c.rows()));  // throws unless M is a basis count
  const Eigen::Index m = c.rows();
  Eigen::VectorXd v(m * (m + 1) / 2);
  Eigen::Index k = 0;
  for (Eigen::Index b = 0; b < m; ++b) {
    for (Eigen::Index a = 0; a < b; ++a) v[k++] = (c(a, b) + c(b, a)) * M_SQRT1_2;
    v[k++] = c(b, b);
  }
  return v;
}

Eigen::MatrixXd coefficients_from_bsss(const Eigen::VectorXd& bsss) {
  const int order = order_from_mode_count(bsss.size(), "coefficients_from_bsss");
  const Eigen::Index m = hemisphere_basis_count(order);
  Eigen::MatrixXd c(m, m);
  Eigen::Index k = 0;
  for (Eigen::Index b = 0; b < m; ++b) {
    for (Eigen::Index a = 0; a < b; ++a) c(a, b) = c(b, a) = bsss[k++] * M_SQRT1_2;
    c(b, b) = bsss[k++];
  }
  return c;
}

Eigen::MatrixXd helmholtz_modes_eval(int order, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  Eigen::MatrixXd out(wi.rows(), helmholtz_mode_count(order));
  helmholtz_modes_eval(order, wi, wr, out);
  return out;
}

void helmholtz_modes_eval(int order, const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
  if (wi.rows() != wr.rows())
    throw ArgumentError("Helmholtz modes: wi has " + std::to_string(wi.rows()) + " rows but wr has " +
                        std::to_string(wr.rows()));
  const long long count = helmholtz_mode_count(order);
  if (out.rows() != wi.rows() || out.cols() != count)
    throw ArgumentError("Helmholtz modes: output " + std::to_string(out.rows()) + " x " + std::to_string(out.cols()) + ", expected " +
                        std::to_string(wi.rows()) + " x " + std::to_string(count));
  const Eigen::MatrixXd ki = hemisphere_basis_matrix(order, wi);  // rows x M
  const Eigen::MatrixXd kr = hemisphere_basis_matrix(order, wr);
  const Eigen::Index m = ki.cols();
#pragma omp parallel for schedule(dynamic, 8) if (wi.rows() * count > 200000)
  for (Eigen::Index b = 0; b < m; ++b) {
    Eigen::Index k = b * (b + 1) / 2;
    for (Eigen::Index a = 0; a < b; ++a, ++k)
      out.col(k) = (ki.col(a).cwiseProduct(kr.col(b)) + ki.col(b).cwiseProduct(kr.col(a))) * M_SQRT1_2;
    out.col(k) = ki.col(b).cwiseProduct(kr.col(b));
  }
}

}  // namespace icobrdf
