#include "icobrdf/mesh/direction_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/horizon.hpp"
#include "icobrdf/mesh/hemi_lattice.hpp"
#include "icobrdf/mesh/icosahedron.hpp"
#include "icobrdf/mesh/tessellation.hpp"

namespace icobrdf {

CellDistribution::CellDistribution(const Eigen::VectorXd& mass, const std::string& what) {
  const Eigen::Index n = mass.size();
  if (n == 0) throw ArgumentError(what + ": no cells");
  cdf_.assign(static_cast<size_t>(n) + 1, 0.0);
  double sum = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    if (!std::isfinite(mass[k]) || mass[k] < 0)
      throw ArgumentError(what + ": cell " + std::to_string(k) + " has mass " + std::to_string(mass[k]) +
                          ", expected a finite value >= 0");
    sum += mass[k];
    cdf_[static_cast<size_t>(k) + 1] = sum;
  }
  if (!(sum > 0)) throw ArgumentError(what + ": every one of the " + std::to_string(n) + " cells has mass 0, nothing to sample");
  p_ = mass / sum;
  for (double& c : cdf_) c /= sum;
  cdf_.back() = 1.0;
}

int CellDistribution::sample(double u, double& u_rescaled) const {
  u = std::min(std::max(u, 0.0), 1.0);
  // First cdf_[j] > u, j in 1..cells: cell j - 1 has cdf_[j-1] <= u < cdf_[j], hence p > 0.
  auto it = std::upper_bound(cdf_.begin() + 1, cdf_.end(), u);
  if (it == cdf_.end()) {  // u = 1: the last cell with p > 0
    it = cdf_.end() - 1;
    while (it != cdf_.begin() + 1 && *(it - 1) == *it) --it;
  }
  const int k = static_cast<int>(it - cdf_.begin()) - 1;
  const double lo = cdf_[static_cast<size_t>(k)], hi = *it;
  u_rescaled = std::min(std::max((u - lo) / (hi - lo), 0.0), std::nextafter(1.0, 0.0));
  return k;
}

DirectionSampler::DirectionSampler(int level)
    : grid_(build_fitting_grid(level, GridKind::EqualArea, false)), locator_(level, "equal-area") {
  const HemiLattice lat(level);
  for (int f = 0; f < static_cast<int>(hemi_icosahedron_faces().size()); ++f) faces_.emplace_back(hemi_face_corners(f));
  const double s = static_cast<double>(lat.scale());
  face_of_.resize(static_cast<size_t>(lat.cells()));
  corners_.resize(static_cast<size_t>(lat.cells()));
  for (int c = 0; c < lat.cells(); ++c) {
    const auto poly = lat.polygon(c);
    if (poly.size() != 3) throw std::logic_error("DirectionSampler: cell " + std::to_string(c) + " is not a triangle");
    face_of_[static_cast<size_t>(c)] = lat.cell(c).face;
    for (int k = 0; k < 3; ++k)
      corners_[static_cast<size_t>(c)][static_cast<size_t>(k)] = Eigen::Vector3d(poly[k][0] / s, poly[k][1] / s, poly[k][2] / s);
  }
}

Eigen::Vector3d DirectionSampler::uniform_in_cell(int cell, double u1, double u2) const {
  if (cell < 0 || cell >= cells())
    throw ArgumentError("uniform_in_cell: cell " + std::to_string(cell) + " outside 0.." + std::to_string(cells() - 1));
  const auto& t = corners_[static_cast<size_t>(cell)];
  const double r = std::sqrt(std::min(std::max(u1, 0.0), 1.0));
  const double b = std::min(std::max(u2, 0.0), 1.0);
  const Eigen::Vector3d l = (1.0 - r) * t[0] + (r * (1.0 - b)) * t[1] + (r * b) * t[2];
  Eigen::Vector3d d = faces_[static_cast<size_t>(face_of_[static_cast<size_t>(cell)])].inverse(l);
  if (d.z() < 0) {  // an equator cell's lower edge, by rounding
    d.z() = 0;
    d.normalize();
  }
  return d;
}

void DirectionSampler::check(const CellDistribution& dist) const {
  if (dist.cells() != cells())
    throw ArgumentError("DirectionSampler: a distribution over " + std::to_string(dist.cells()) + " cells, expected " +
                        std::to_string(cells()) + " (level " + std::to_string(level()) + ")");
}

DirectionSample DirectionSampler::sample(const CellDistribution& dist, double u1, double u2) const {
  check(dist);
  DirectionSample out;
  double u = 0;
  out.cell = dist.sample(u1, u);
  out.direction = uniform_in_cell(out.cell, u, u2);
  out.pdf = dist.probability(out.cell) / grid_.solid_angles[out.cell];
  return out;
}

double DirectionSampler::pdf(const CellDistribution& dist, const Eigen::Vector3d& w) const {
  check(dist);
  if (w.z() < -kHorizonSlack) return 0.0;
  const int k = locator_.locate(w);  // ArgumentError for a non-unit w
  return dist.probability(k) / grid_.solid_angles[k];
}

Eigen::VectorXd DirectionSampler::pdf(const CellDistribution& dist, const RowMatrix3d& w) const {
  check(dist);
  RowMatrix3d lookup = w;  // rows below the horizon are looked up at the pole and given 0
  for (Eigen::Index i = 0; i < w.rows(); ++i)
    if (w(i, 2) < -kHorizonSlack) lookup.row(i) << 0, 0, 1;
  Eigen::VectorXi cells;
  locator_.locate(lookup, cells);  // ArgumentError for a non-unit row
  Eigen::VectorXd out(w.rows());
  for (Eigen::Index i = 0; i < w.rows(); ++i)
    out[i] = w(i, 2) < -kHorizonSlack ? 0.0 : dist.probability(cells[i]) / grid_.solid_angles[cells[i]];
  return out;
}

}  // namespace icobrdf
