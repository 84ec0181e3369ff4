#include "icobrdf/mesh/snyder_projection.hpp"

#include <algorithm>

namespace icobrdf {

SnyderProjection::SnyderProjection(const std::array<Eigen::Vector3d, 3>& corners) : v_(corners) {
  c_ = (v_[0] + v_[1] + v_[2]).normalized();
  // a = arc CM of the regular icosahedron, in closed form: in the right triangle C M V (angles 60, 36,
  // 90 deg) cos a = cos 36 / sin 60, hence tan a = sqrt(2 - phi) / phi = 1 / phi^2. The same constant for
  // every face (so the map has one form on all faces).
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  a_ = std::atan(1.0 / (phi * phi));
  sin_a_ = std::sin(a_);
  cos_a_ = std::cos(a_);
  tan_half_a_ = std::tan(a_ / 2.0);
  const double tan_b_max = sin_a_ * std::sqrt(3.0);  // tan b = sin a tan Az at Az = 60 deg
  targ_max_ = tan_half_a_ * tan_b_max / (1.0 + std::sqrt(1.0 + tan_b_max * tan_b_max));
  // Planar face: equilateral, centroid at the origin, area kFaceArea = 3 sqrt(3) r^2.
  r_ = std::sqrt(kFaceArea / (3.0 * std::sqrt(3.0)));
  const double big_r = 2.0 * r_;  // circumradius
  std::array<Eigen::Vector2d, 3> p;
  for (int k = 0; k < 3; ++k) {
    const double ang = M_PI / 2.0 + 2.0 * M_PI * k / 3.0;
    p[k] = big_r * Eigen::Vector2d(std::cos(ang), std::sin(ang));
  }
  for (int s = 0; s < 6; ++s) {
    const int k = s / 2;
    const int m = (s % 2 == 0) ? (k + 1) % 3 : (k + 2) % 3;
    const int o = 3 - k - m;
    Frame& f = frames_[s];
    // Sphere: tangent at C towards the midpoint of the edge opposite corner m (between corners k and o),
    // and the orthogonal tangent on the side of corner k.
    const Eigen::Vector3d mid = (v_[k] + v_[o]).normalized();
    f.u = (mid - mid.dot(c_) * c_).normalized();
    Eigen::Vector3d w = v_[k] - v_[k].dot(c_) * c_;
    f.w = (w - w.dot(f.u) * f.u).normalized();
    // Plane: the same construction.
    const Eigen::Vector2d pm = (p[k] + p[o]) / 2.0;
    const Eigen::Vector2d ex = pm.normalized();
    Eigen::Vector2d ey = p[k] - p[k].dot(ex) * ex;
    ey.normalize();
    for (int j = 0; j < 3; ++j) {
      // l_j = 1/3 + (2 / (3 R^2)) p . P_j for the equilateral triangle centred at the origin.
      f.gx[j] = 2.0 / (3.0 * big_r * big_r) * ex.dot(p[j]);
      f.gy[j] = 2.0 / (3.0 * big_r * big_r) * ey.dot(p[j]);
      f.hx[j] = p[j].dot(ex);
      f.hy[j] = p[j].dot(ey);
    }
  }
}

Eigen::Vector3d SnyderProjection::inverse(const Eigen::Vector3d& l, int s) const {
  const Frame& f = frames_[s];
  const double x = l[0] * f.hx[0] + l[1] * f.hx[1] + l[2] * f.hx[2];
  const double y = l[0] * f.hy[0] + l[1] * f.hy[1] + l[2] * f.hy[2];
  if (!(x > 0)) return c_;  // the face centre (x = 0 only there inside the sub-triangle)
  const double tan_azp = y / x;
  const double e = 0.5 * r_ * r_ * tan_azp;                 // area of C M Q
  const double tbh = std::tan(0.5 * e) / tan_half_a_;       // tan(b/2)
  const double tbh2 = tbh * tbh;
  const double tan_b = 2.0 * tbh / (1.0 - tbh2);
  const double cos_b = (1.0 - tbh2) / (1.0 + tbh2);
  const double tan_az = tan_b / sin_a_;
  const double sin_half_q = std::sqrt(0.5 * (1.0 - cos_a_ * cos_b));
  const double sh = x * sin_half_q / r_;                    // sin(z/2)
  const double cos_z = 1.0 - 2.0 * sh * sh;
  const double sin_z = 2.0 * sh * std::sqrt(std::max(0.0, 1.0 - sh * sh));
  const double cos_az = 1.0 / std::sqrt(1.0 + tan_az * tan_az);
  const double sin_az = tan_az * cos_az;
  Eigen::Vector3d d = cos_z * c_ + sin_z * (cos_az * f.u + sin_az * f.w);
  return d / d.norm();
}

}  // namespace icobrdf
