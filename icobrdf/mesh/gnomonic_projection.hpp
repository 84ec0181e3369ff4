#pragma once
// Gnomonic (central) projection between one icosahedron face and its flat triangle: the geodesic
// (non-equal-area) baseline. Planar coordinates are barycentric coordinates (l0, l1, l2), sum 1, of the
// flat triangle V0 V1 V2 (unit corners); a planar point p = sum l_k V_k maps to p / |p|. Straight lines map
// to great circles, so lattice sub-triangles map to geodesic spherical triangles.
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>

namespace icobrdf {

class GnomonicProjection {
 public:
  explicit GnomonicProjection(const std::array<Eigen::Vector3d, 3>& corners);

  // Unit direction -> barycentric coordinates of its central projection onto the face plane.
  Eigen::Vector3d forward(const Eigen::Vector3d& d) const {
    const double a = d.dot(dual_[0]), b = d.dot(dual_[1]), c = d.dot(dual_[2]);
    const double s = a + b + c;
    return Eigen::Vector3d(a / s, b / s, c / s);
  }
  Eigen::Vector3d inverse(const Eigen::Vector3d& l) const {
    return (l[0] * v_[0] + l[1] * v_[1] + l[2] * v_[2]).normalized();
  }
  // dOmega / dA at the planar point with barycentric l: h / |p|^3 (h = distance of the plane from 0).
  double jacobian(const Eigen::Vector3d& l) const;
  double flat_area() const { return flat_area_; }  // area of the flat face V0 V1 V2

 private:
  std::array<Eigen::Vector3d, 3> v_;
  std::array<Eigen::Vector3d, 3> dual_;  // rows of [V0 V1 V2]^-1
  double h_ = 0, flat_area_ = 0;
};

// Solid angle of the geodesic spherical triangle a b c (unit vectors, counter-clockwise seen from
// outside), by Van Oosterom and Strackee: tan(Omega/2) = a.(b x c) / (1 + a.b + b.c + c.a).
double spherical_triangle_solid_angle(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c);

}  // namespace icobrdf
