#include "mesh/cell_locator.hpp"

#include <cmath>
#include <string>

#include "core/error.hpp"
#include "mesh/hemi_lattice.hpp"
#include "mesh/icosahedron.hpp"

namespace icobrdf {
namespace {

// Inputs are normalized vectors; 1e-10 on the norm allows any rounding of a normalization while
// rejecting vectors that were never normalized.
constexpr double kUnitTol = 1e-10;
// Directions computed on the equator may carry a rounding-sized negative z.
constexpr double kHorizonTol = 1e-12;

std::array<Eigen::Vector3d, 3> corners_of(const HemiFace& f) {
  const auto& v = icosahedron_vertices();
  return {v[f.v[0]], v[f.v[1]], v[f.v[2]]};
}

}  // namespace

CellLocator::CellLocator(int level, const std::string& kind) : level_(level), n_(0), cells_(0), kind_(kind) {
  if (kind != "equal-area" && kind != "geodesic")
    throw ArgumentError("unknown grid kind '" + kind + "': expected 'equal-area' or 'geodesic'");
  equal_area_ = kind == "equal-area";
  const HemiLattice lat(level);
  n_ = lat.n();
  cells_ = lat.cells();
  table_ = lat.table();
  const auto& faces = hemi_icosahedron_faces();
  for (size_t f = 0; f < faces.size(); ++f) {
    cx_[f] = faces[f].centre.x();
    cy_[f] = faces[f].centre.y();
    cz_[f] = faces[f].centre.z();
    if (equal_area_)
      snyder_.emplace_back(corners_of(faces[f]));
    else
      gnomonic_.emplace_back(corners_of(faces[f]));
  }
}

int CellLocator::face_of(const Eigen::Vector3d& d) const {
  int best = 0;
  double bd = cx_[0] * d.x() + cy_[0] * d.y() + cz_[0] * d.z();
  for (int f = 1; f < 12; ++f) {
    const double s = cx_[f] * d.x() + cy_[f] * d.y() + cz_[f] * d.z();
    if (s > bd) {
      bd = s;
      best = f;
    }
  }
  return best;
}

int CellLocator::lattice_triangle(int n, double l1, double l2) {
  int i = static_cast<int>(std::floor(l1));
  int j = static_cast<int>(std::floor(l2));
  if (i < 0) i = 0;
  if (i > n - 1) i = n - 1;
  if (j < 0) j = 0;
  if (j > n - 1 - i) j = n - 1 - i;
  const int down = (i + j <= n - 2 && (l1 - i) + (l2 - j) > 1.0) ? 1 : 0;
  return HemiLattice::lattice_index(n, i, j, down);
}

int CellLocator::locate_unchecked(const Eigen::Vector3d& d) const {
  const int f = face_of(d);
  Eigen::Vector3d l = equal_area_ ? snyder_[f].forward(d) : gnomonic_[f].forward(d);
  return table_[static_cast<size_t>(f) * n_ * n_ + lattice_triangle(n_, l[1] * n_, l[2] * n_)];
}

int CellLocator::locate(const Eigen::Vector3d& d) const {
  const double nn = d.squaredNorm();
  if (!(std::abs(nn - 1.0) <= kUnitTol) || !(d.z() >= -kHorizonTol))
    throw ArgumentError("CellLocator::locate: direction (" + std::to_string(d.x()) + ", " + std::to_string(d.y()) + ", " +
                        std::to_string(d.z()) + ") is not a unit vector with z >= 0 (norm^2 = " + std::to_string(nn) + ")");
  return locate_unchecked(d);
}

void CellLocator::locate(const RowMatrix3d& dirs, Eigen::VectorXi& cells) const {
  cells.resize(dirs.rows());
  for (Eigen::Index k = 0; k < dirs.rows(); ++k) cells[k] = locate(Eigen::Vector3d(dirs(k, 0), dirs(k, 1), dirs(k, 2)));
}

}  // namespace icobrdf
