#include "core/spectrum_ops.hpp"

#include <cmath>
#include <algorithm>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/hemisphere_basis.hpp"

namespace icobrdf {

Eigen::VectorXd evaluate_coefficients(const Eigen::MatrixXd& c, int order, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  const int m = hemisphere_basis_count(order);
  if (c.rows() != m || c.cols() != m)
    throw ArgumentError("evaluate: coefficient matrix is " + std::to_string(c.rows()) + " x " + std::to_string(c.cols()) +
                        ", expected " + std::to_string(m) + " x " + std::to_string(m) + " for order " + std::to_string(order));
  if (wi.rows() != wr.rows()) throw ArgumentError("evaluate: incident and remitted direction counts differ");
  const Eigen::Index n = wi.rows();
  for (const RowMatrix3d* d : {&wi, &wr})
    for (Eigen::Index r = 0; r < n; ++r)
      if (!d->row(r).allFinite() || !((*d)(r, 2) >= -1e-12))
        throw ArgumentError(std::string("evaluate: ") + (d == &wi ? "incident" : "remitted") + " direction " + std::to_string(r) +
                            " is not a finite direction with z >= 0");
  // Blocks of kEvalBlock pairs: K(w_i) and K(w_r) (block x M, lane-parallel evaluation), T = K(w_i) C by a
  // small GEMM, then the row-wise dot of T with K(w_r). Everything stays in cache; threads take blocks.
  constexpr Eigen::Index kEvalBlock = 256;
  static const double kOnes[kBasisLanes] = {1.0, 1.0, 1.0, 1.0};
  Eigen::VectorXd out(n);
  const Eigen::Index blocks = (n + kEvalBlock - 1) / kEvalBlock;
#pragma omp parallel if (n > 4 * kEvalBlock)
  {
    std::vector<double> scratch(static_cast<size_t>(hemisphere_basis_lanes_scratch(order))), k(static_cast<size_t>(m * kBasisLanes));
    Eigen::MatrixXd ki(kEvalBlock, m), kr(kEvalBlock, m), t(kEvalBlock, m);
    Eigen::VectorXd acc(kEvalBlock);
#pragma omp for schedule(static)
    for (Eigen::Index b = 0; b < blocks; ++b) {
      const Eigen::Index p0 = b * kEvalBlock, np = std::min(kEvalBlock, n - p0);
      for (int side = 0; side < 2; ++side) {
        const RowMatrix3d& d = side == 0 ? wi : wr;
        Eigen::MatrixXd& kk = side == 0 ? ki : kr;
        for (Eigen::Index g0 = 0; g0 < kEvalBlock; g0 += kBasisLanes) {
          alignas(32) double x[kBasisLanes], y[kBasisLanes], z[kBasisLanes];
          for (int l = 0; l < kBasisLanes; ++l) {
            const Eigen::Index r = p0 + std::min<Eigen::Index>(g0 + l, np - 1);  // padding repeats the last pair
            x[l] = d(r, 0);
            y[l] = d(r, 1);
            z[l] = d(r, 2);
          }
          hemisphere_basis_eval_lanes(order, x, y, z, kOnes, scratch.data(), k.data());
          for (int j = 0; j < m; ++j)
            for (int l = 0; l < kBasisLanes; ++l) kk(g0 + l, j) = k[static_cast<size_t>(j) * kBasisLanes + l];
        }
      }
      t.noalias() = ki * c;
      acc.setZero();
      for (int j = 0; j < m; ++j) acc += t.col(j).cwiseProduct(kr.col(j));
      out.segment(p0, np) = acc.head(np);
    }
  }
  return out;
}

Eigen::MatrixXd rotation_matrix(int order, double angle) {
  // K_n^l(phi - a): for l > 0, cos(l(phi - a)) = cos(l phi) cos(l a) + sin(l phi) sin(l a), and
  // az_{-l}(phi) = sin(l phi); sin(l(phi - a)) = sin(l phi) cos(l a) - cos(l phi) sin(l a).
  // So K_l' = cos(la) K_l + sin(la) K_{-l},  K_{-l}' = cos(la) K_{-l} - sin(la) K_l; f' = K'^T C K' = K^T R^T... :
  // with K' = A K (A the matrix above), f' = K^T A^T C A K, hence C' = A^T C A and R = A^T.
  const int m = hemisphere_basis_count(order);
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m, m);
  for (int j = 0; j < m; ++j) {
    const auto nl = ansi_to_nl(j);
    if (nl.l == 0) {
      a(j, j) = 1.0;
    } else if (nl.l > 0) {
      const int jm = ansi_index(nl.n, -nl.l);
      const double cs = std::cos(nl.l * angle), sn = std::sin(nl.l * angle);
      a(j, j) = cs;
      a(j, jm) = sn;
      a(jm, jm) = cs;
      a(jm, j) = -sn;
    }
  }
  return a.transpose();
}

Eigen::MatrixXd rotate_coefficients(const Eigen::MatrixXd& c, int order, double angle) {
  const Eigen::MatrixXd r = rotation_matrix(order, angle);
  return r * c * r.transpose();
}

Eigen::VectorXd cosine_moments(int order) {
  // cos(theta) = 1 - rho^2 and dOmega = 2 rho drho dphi (Lambert map), so with R_0^0 = 1 and
  // R_2^0 = 2 rho^2 - 1:  cos(theta) = 1/2 - R_2^0 / 2.
  //   K_0^0 = sqrt(1/pi) / sqrt(2),  K_2^0 = sqrt(3/pi) R_2^0 / sqrt(2).
  //   e_0 = integral cos dOmega = pi.
  //   e_{2,0} = -1/2 integral R_2^0 K_2^0 dOmega = -1/2 * sqrt(3/(2 pi)) * integral (R_2^0)^2 dOmega
  //           = -1/2 * sqrt(3/(2 pi)) * (2 pi / 3)  [integral (R_2^0)^2 2 rho drho dphi = 2 pi * 2/(2*3)... = 2 pi/3]
  // and e_0 expressed on K_0^0: integral K_0^0 cos dOmega = sqrt(1/(2 pi)) * pi.
  const int m = hemisphere_basis_count(order);
  Eigen::VectorXd e = Eigen::VectorXd::Zero(m);
  e[ansi_index(0, 0)] = std::sqrt(1.0 / (2.0 * M_PI)) * M_PI;
  if (order >= 2) e[ansi_index(2, 0)] = -0.5 * std::sqrt(3.0 / (2.0 * M_PI)) * (2.0 * M_PI / 3.0);
  return e;
}

Eigen::VectorXd spectral_albedo(const Eigen::MatrixXd& c, int order, const RowMatrix3d& wi) {
  return hemisphere_basis_matrix(order, wi) * (c * cosine_moments(order));
}

double coefficient_asymmetry(const Eigen::MatrixXd& c) {
  const double n = c.norm();
  return n == 0.0 ? 0.0 : 0.5 * (c - c.transpose()).norm() / n;
}

}  // namespace icobrdf
