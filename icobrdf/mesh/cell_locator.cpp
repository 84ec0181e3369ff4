#include "icobrdf/mesh/cell_locator.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/horizon.hpp"
#include "icobrdf/mesh/hemi_lattice.hpp"
#include "icobrdf/mesh/icosahedron.hpp"
#include "icobrdf/mesh/tessellation_mesh.hpp"

namespace icobrdf {
namespace {

// Inputs are normalized vectors; 1e-10 on the norm allows any rounding of a normalization while
// rejecting vectors that were never normalized.
constexpr double kUnitTol = 1e-10;
// Face centres have coordinates 0 or >= 0.35: 1e-9 tells zero from non-zero with a wide margin.
constexpr double kFoldTol = 1e-9;

std::array<Eigen::Vector3d, 3> corners_of(const HemiFace& f) {
  const auto& v = icosahedron_vertices();
  return {v[f.v[0]], v[f.v[1]], v[f.v[2]]};
}

}  // namespace

CellLocator::CellLocator(int level, const std::string& kind) : level_(level), n_(0), cells_(0), kind_(kind) {
  equal_area_ = hemi_icosahedral_kind(kind) == GridKind::EqualArea;
  const HemiLattice lat(level);
  n_ = lat.n();
  cells_ = lat.cells();
  table_ = lat.table();
  const auto& faces = hemi_icosahedron_faces();
  for (size_t f = 0; f < faces.size(); ++f) {
    if (equal_area_)
      snyder_.emplace_back(corners_of(faces[f]));
    else
      gnomonic_.emplace_back(corners_of(faces[f]));
  }
  dense_faces_ = 0;
  for (int f = 0; f < static_cast<int>(faces.size()) && !faces[f].bisected; ++f) {
    bool dense = true;
    for (int k = 0; k < n_ * n_; ++k) dense = dense && table_[static_cast<size_t>(f) * n_ * n_ + k] == f * n_ * n_ + k;
    if (!dense) break;
    dense_faces_ = f + 1;
  }
  if (equal_area_) {
    sin_a_ = std::sin(snyder_[0].arc_centre_midpoint());
    cos_a_ = std::cos(snyder_[0].arc_centre_midpoint());
    tan_half_a_ = std::tan(snyder_[0].arc_centre_midpoint() / 2);
    targ_max_ = snyder_[0].atan_argument_max();
    r_ = snyder_[0].inradius();
  }
  if (equal_area_)
    for (size_t f = 0; f < faces.size(); ++f)
      for (int sub = 0; sub < 6; ++sub) {
        const SnyderProjection& pr = snyder_[f];
        const SnyderProjection::Frame& fr = pr.frame(sub);
        SubFrame sf;
        for (int i = 0; i < 3; ++i) {
          sf.c[i] = pr.centre()[i];
          sf.u[i] = fr.u[i];
          sf.w[i] = fr.w[i];
        }
        sf.gx1 = fr.gx[1];
        sf.gy1 = fr.gy[1];
        sf.gx2 = fr.gx[2];
        sf.gy2 = fr.gy[2];
        frames_.push_back(sf);
      }
  // Quadrant candidates and the face each becomes under the sign flips (matched by centre).
  int q = 0;
  std::array<int, 4> cand{};
  for (size_t f = 0; f < faces.size(); ++f)
    if (faces[f].centre.x() > -kFoldTol && faces[f].centre.y() > -kFoldTol) {
      if (q == 4) throw std::logic_error("CellLocator: more than 4 face centres in a quadrant");
      cand[q++] = static_cast<int>(f);
    }
  if (q != 4) throw std::logic_error("CellLocator: expected 4 face centres in a quadrant");
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector3d& c = faces[cand[k]].centre;
    qx_[k] = c.x();
    qy_[k] = c.y();
    qz_[k] = c.z();
    for (int signs = 0; signs < 4; ++signs) {
      const Eigen::Vector3d im((signs & 1) ? -c.x() : c.x(), (signs & 2) ? -c.y() : c.y(), c.z());
      unfold_[signs][k] = -1;
      for (size_t f = 0; f < faces.size(); ++f)
        if ((faces[f].centre - im).norm() < kFoldTol) unfold_[signs][k] = static_cast<int>(f);
      if (unfold_[signs][k] < 0) throw std::logic_error("CellLocator: face set not mirror symmetric");
    }
  }
}

void CellLocator::locate_block(const double* p, int count, int* out) const {
  using Arr = Eigen::Array<double, kBlock, 1>;
  int face[kBlock];
  if (!equal_area_) {
    for (int k = 0; k < count; ++k) {
      const Eigen::Vector3d d(p[3 * k], p[3 * k + 1], p[3 * k + 2]);
      const int f = face_of(d.x(), d.y(), d.z());
      const Eigen::Vector3d l = gnomonic_[f].forward(d);
      const int idx = lattice_triangle(n_, l[1] * n_, l[2] * n_);
      out[k] = f < dense_faces_ ? f * n_ * n_ + idx : table_[static_cast<size_t>(f) * n_ * n_ + idx];
    }
    return;
  }
  // Pass 1 (scalar): face, sub-triangle, tangent components and the constants of the frame.
  Arr dc, du, dw0, gx1, gy1, gx2, gy2;
  // The projection's constants are the same on every face (those of the regular icosahedron).
  const double sin_a = sin_a_, cos_a = cos_a_, tha = tan_half_a_, targ_max = targ_max_, r = r_;
  for (int k = 0; k < kBlock; ++k) {
    const int kk = k < count ? k : 0;  // pad the block with the first direction
    const double x = p[3 * kk], y = p[3 * kk + 1], z = p[3 * kk + 2];
    const int f = face_of(x, y, z);
    face[k] = f;
    const SnyderProjection& pr = snyder_[f];
    const Eigen::Vector3d& v0 = pr.corner(0);
    const Eigen::Vector3d& v1 = pr.corner(1);
    const Eigen::Vector3d& v2 = pr.corner(2);
    const int s = SnyderProjection::sub_triangle(x * v0.x() + y * v0.y() + z * v0.z(), x * v1.x() + y * v1.y() + z * v1.z(),
                                                 x * v2.x() + y * v2.y() + z * v2.z());
    const SubFrame& fr = frames_[6 * f + s];
    dc[k] = x * fr.c[0] + y * fr.c[1] + z * fr.c[2];
    du[k] = x * fr.u[0] + y * fr.u[1] + z * fr.u[2];
    dw0[k] = x * fr.w[0] + y * fr.w[1] + z * fr.w[2];
    gx1[k] = fr.gx1;
    gy1[k] = fr.gy1;
    gx2[k] = fr.gx2;
    gy2[k] = fr.gy2;
  }
  // Pass 2 (vectorized): the forward projection of SnyderProjection::forward_xy, lane by lane.
  const Arr dw = dw0.max(0.0);
  const Arr sdw = sin_a * dw;
  const Arr big_s = (du * du + sdw * sdw).sqrt();
  const Arr den = du + big_s;
  const auto ok = den > 0.0;
  const Arr t = (tha * sdw / ok.select(den, 1.0)).min(targ_max);  // as in SnyderProjection::forward_xy
  const Arr t2 = t * t;
  const Arr at = t * (1.0 + t2 * (-1.0 / 3 + t2 * (1.0 / 5 + t2 * (-1.0 / 7 + t2 * (1.0 / 9 + t2 * (-1.0 / 11 + t2 * (1.0 / 13 - t2 / 15)))))));
  const Arr e = 2.0 * at;
  const Arr omc = 1.0 - dc;
  const Arr chord2 = omc * omc + du * du + dw0 * dw0;
  const Arr ratio = chord2 * big_s / ok.select(2.0 * (big_s - cos_a * du), 1.0);
  const Arr x = ok.select(r * ratio.sqrt(), 0.0);
  const Arr y = x * (2.0 * e / (r * r));
  const Arr l1 = (1.0 / 3.0 + x * gx1 + y * gy1) * n_;
  const Arr l2 = (1.0 / 3.0 + x * gx2 + y * gy2) * n_;
  // Pass 3 (scalar): lattice triangle and cell.
  for (int k = 0; k < count; ++k) {
    const int f = face[k];
    const int idx = lattice_triangle(n_, l1[k], l2[k]);
    // Leading whole faces are numbered densely (cell = f n^2 + index, checked against the table at
    // construction); the table is read only for the others, which keeps it out of the cache.
    out[k] = f < dense_faces_ ? f * n_ * n_ + idx : table_[static_cast<size_t>(f) * n_ * n_ + idx];
  }
}

void CellLocator::check(const double* p, Eigen::Index k) {
  const double nn = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
  if (!(std::abs(nn - 1.0) <= kUnitTol) || !(p[2] >= -kHorizonSlack))
    throw ArgumentError("cell lookup: direction " + std::to_string(k) + " (" + std::to_string(p[0]) + ", " +
                        std::to_string(p[1]) + ", " + std::to_string(p[2]) +
                        ") is not a unit vector with z >= 0 (norm^2 = " + std::to_string(nn) + ")");
}

int CellLocator::locate(const Eigen::Vector3d& d) const {
  check(d.data(), 0);
  int out;
  locate_block(d.data(), 1, &out);
  return out;
}

void CellLocator::locate(const RowMatrix3d& dirs, Eigen::VectorXi& cells) const {
  const Eigen::Index n = dirs.rows();
  for (Eigen::Index k = 0; k < n; ++k) check(dirs.data() + 3 * k, k);
  cells.resize(n);
  for (Eigen::Index k = 0; k < n; k += kBlock)
    locate_block(dirs.data() + 3 * k, static_cast<int>(std::min<Eigen::Index>(kBlock, n - k)), cells.data() + k);
}

}  // namespace icobrdf
