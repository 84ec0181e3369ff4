#include "icobrdf/core/spectrum/spectrum_ops.hpp"

#include <cmath>
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_evaluation.hpp"
#include "icobrdf/core/spectrum/spectrum_tile.hpp"
#include "icobrdf/core/support/huge_pages.hpp"


namespace icobrdf {

namespace {

// Pairs per block: a multiple of every target's register tile (24, 8, 4, 2 pairs); the basis of both sides
// for a block (2 x 192 x M doubles, 138 KB at order 8) stays in L2.
constexpr Eigen::Index kEvalBlock = 192;

}  // namespace

Eigen::VectorXd evaluate_coefficients(const Eigen::MatrixXd& c, int order, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  const int m = hemisphere_basis_count(order);
  if (c.rows() != m || c.cols() != m)
    throw ArgumentError("evaluate: coefficient matrix is " + std::to_string(c.rows()) + " x " + std::to_string(c.cols()) +
                        ", expected " + std::to_string(m) + " x " + std::to_string(m) + " for order " + std::to_string(order));
  if (wi.rows() != wr.rows()) throw ArgumentError("evaluate: incident and remitted direction counts differ");
  const Eigen::Index n = wi.rows();
  // Blocks of kEvalBlock pairs: K(w_i) and K(w_r) (block x M, column-major, by the block basis kernel), then
  // f = rowwise dot(K(w_i) C, K(w_r)) by the dispatched tile (icobrdf/core/spectrum/spectrum_tile.hpp), which never stores
  // K(w_i) C. Threads take blocks; each pair's value depends only on its own directions, so results do not
  // depend on threads. Each block's directions are checked just before they are evaluated (one pass over
  // memory instead of two); the first invalid row of each side is reported after the loop.
  const PackedSpectrum packed = pack_spectrum(c, order);
  const Eigen::Index kr_cols = spectrum_tile_columns(packed);
  Eigen::VectorXd out(n);
  advise_huge_pages(out.data(), sizeof(double) * static_cast<size_t>(n));
  const Eigen::Index blocks = (n + kEvalBlock - 1) / kEvalBlock;
  Eigen::Index bad_i = n, bad_r = n;
#pragma omp parallel if (n > 4 * kEvalBlock) reduction(min : bad_i, bad_r)
  {
    // Zeroed once: kr's padding columns must be finite, and rows past a short last block too.
    Eigen::MatrixXd ki = Eigen::MatrixXd::Zero(kEvalBlock, m), kr = Eigen::MatrixXd::Zero(kEvalBlock, kr_cols);
    Eigen::VectorXd f(kEvalBlock);
#pragma omp for schedule(static)
    for (Eigen::Index b = 0; b < blocks; ++b) {
      const Eigen::Index p0 = b * kEvalBlock, np = std::min(kEvalBlock, n - p0);
      if (const Eigen::Index r = first_invalid_direction(wi.data() + 3 * p0, np); r >= 0) bad_i = std::min(bad_i, p0 + r);
      if (const Eigen::Index r = first_invalid_direction(wr.data() + 3 * p0, np); r >= 0) bad_r = std::min(bad_r, p0 + r);
      if (packed.isotropic) {
        isotropic_form_block(order, packed.radial_blocks.data(), np, wi.data() + 3 * p0, wr.data() + 3 * p0, out.data() + p0);
        continue;
      }
      hemisphere_basis_block(order, np, wi.data() + 3 * p0, ki.data(), kEvalBlock);
      hemisphere_basis_block(order, np, wr.data() + 3 * p0, kr.data(), kEvalBlock);
      spectrum_tile(packed, np, ki.data(), kr.data(), kEvalBlock, f.data());
      out.segment(p0, np) = f.head(np);
    }
  }
  for (const auto& [side, r] : {std::pair<const char*, Eigen::Index>{"incident", bad_i}, {"remitted", bad_r}})
    if (r < n)
      throw ArgumentError(std::string("evaluate: ") + side + " direction " + std::to_string(r) + " is not a finite direction with z >= 0");
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
  // In chunks of directions: the basis of all of them at once would be a cells x modes matrix (3.7 GB at
  // level 7, order 74), as large as the operators a split fit avoids holding.
  constexpr Eigen::Index kChunk = 4096;
  const Eigen::VectorXd moments = c * cosine_moments(order);
  Eigen::VectorXd out(wi.rows());
  for (Eigen::Index i0 = 0; i0 < wi.rows(); i0 += kChunk) {
    const Eigen::Index k = std::min(kChunk, wi.rows() - i0);
    out.segment(i0, k) = hemisphere_basis_matrix(order, RowMatrix3d(wi.middleRows(i0, k))) * moments;
  }
  return out;
}

double coefficient_asymmetry(const Eigen::MatrixXd& c) {
  const double n = c.norm();
  return n == 0.0 ? 0.0 : 0.5 * (c - c.transpose()).norm() / n;
}

}  // namespace icobrdf
