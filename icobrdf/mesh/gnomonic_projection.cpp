#include "icobrdf/mesh/gnomonic_projection.hpp"

#include <Eigen/LU>

#include <cmath>

namespace icobrdf {

GnomonicProjection::GnomonicProjection(const std::array<Eigen::Vector3d, 3>& corners) : v_(corners) {
  Eigen::Matrix3d m;
  for (int k = 0; k < 3; ++k) m.col(k) = v_[k];
  const Eigen::Matrix3d inv = m.inverse();
  for (int k = 0; k < 3; ++k) dual_[k] = inv.row(k).transpose();
  const Eigen::Vector3d n = (v_[1] - v_[0]).cross(v_[2] - v_[0]);
  flat_area_ = 0.5 * n.norm();
  h_ = v_[0].dot(n.normalized());
}

double GnomonicProjection::jacobian(const Eigen::Vector3d& l) const {
  const double r = (l[0] * v_[0] + l[1] * v_[1] + l[2] * v_[2]).norm();
  return h_ / (r * r * r);
}

double spherical_triangle_solid_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double num = a.dot(b.cross(c));
  const double den = 1.0 + a.dot(b) + b.dot(c) + c.dot(a);
  return 2.0 * std::atan2(num, den);
}

}  // namespace icobrdf
