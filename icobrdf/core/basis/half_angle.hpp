#pragma once
// Half-angle / difference coordinates of a direction pair (Rusinkiewicz 1998).
//
// Conventions (SPEC-NOTES): unit vectors, normal +z, w_i and w_r both pointing away from the surface.
//   h = normalize(w_i + w_r), (theta_h, phi_h) its angles;
//   d = Ry(-theta_h) Rz(-phi_h) w_i, i.e. w_i in the frame whose pole is h, (theta_d, phi_d) its angles.
// Inverse: w_i = Rz(phi_h) Ry(theta_h) d and w_r = Rz(phi_h) Ry(theta_h) (-d_x, -d_y, d_z), which is
// w_r = 2 (w_i . h) h - w_i (w_r is the mirror image of w_i about h).
//
// Numerics: no trigonometry is needed for the vectors. With s = w_i + w_r and m = w_i - w_r
// (s . m = 0 for unit vectors), R s = |s| e_z, so d = (R m / 2)_xy + (|s| / 2) e_z: theta_d =
// atan2(|m|, |s|) keeps full relative accuracy everywhere, and exchanging w_i and w_r negates m exactly,
// so the swap acts on the computed d bitwise (see below). Angles use atan2(sqrt(x^2 + y^2), z), never
// acos. Where h = n (h_x = h_y = 0) phi_h = 0 (the frame rotation is the identity); where d is the pole,
// phi_d = 0.
// Degenerate pair: w_i = -w_r (both on the horizon, opposite) has no h. There h = n is used (fallback),
// so d = w_i, theta_d = pi/2, and the inverse gives back w_r = (-d_x, -d_y, d_z) = -w_i: nothing is NaN
// and the round trip holds. The fallback is taken when |s|^2 < DBL_MIN (|s| < 1.5e-154); the round trip
// error there is at most |s| / 2.
// Round trip accuracy: a few ulps, except near that pair: (h, d) with |d| = 1 cannot carry
// |w_i|^2 - |w_r|^2 (a few ulps for vectors unit to rounding), so the round trip loses m.h =
// (|w_i|^2 - |w_r|^2) / |s|, about 4 eps / |w_i + w_r|.
//
// Symmetries:
//  - Exchanging w_i and w_r leaves h unchanged and maps d -> (-d_x, -d_y, d_z), i.e. theta_d -> theta_d,
//    phi_d -> phi_d + pi. A reciprocal BRDF f(w_i, w_r) = f(w_r, w_i) is therefore pi-periodic in phi_d.
//  - Rotating both directions about the normal by a adds a to phi_h and leaves (theta_h, theta_d, phi_d)
//    unchanged (d is expressed in the frame that rotates with h). An isotropic BRDF is a function of
//    (theta_h, theta_d, phi_d) alone.
//  - For w_i, w_r on or above the horizon: h_z >= 0, and d_z = w_i . h = |s| / 2 >= 0 (theta_d <= pi/2);
//    both are on or above the horizon iff tan(theta_h) tan(theta_d) |cos(phi_d)| <= 1, since
//    w_{i,r} . n = cos(theta_h) d_z -/+ sin(theta_h) d_x.
//
// Measure: dw_i dw_r = 4 cos(theta_d) dw_h dw_d. Derivation: for fixed w_i, the map w_r -> h has the
// Jacobian dw_h / dw_r = 1 / (4 (w_i . h)) (the classical half-vector Jacobian: w_r = 2 (w_i . h) h - w_i
// sweeps twice the angle of h around w_i, and the area element on the sphere scales by 4 (w_i . h)), so
// dw_i dw_r = 4 (w_i . h) dw_i dw_h. For fixed h, w_i -> d is a rotation, which preserves solid angle, so
// dw_i dw_h = dw_d dw_h. Finally w_i . h = d_z = cos(theta_d). (h over the sphere and d over the upper
// hemisphere of its frame cover every pair once: integral of 4 cos(theta_d) over d is 4 pi, times 4 pi for
// h, gives (4 pi)^2.) Lambert in this measure: cos(theta_i) cos(theta_r) = cos^2(theta_d) cos^2(theta_h) -
// sin^2(theta_d) cos^2(phi_d) sin^2(theta_h).
#include <Eigen/Core>

#include <cfloat>
#include <cmath>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

struct HalfAngleCoords {
  double theta_h;  // [0, pi/2] for pairs on or above the horizon
  double phi_h;    // (-pi, pi]; 0 at h = n
  double theta_d;  // [0, pi/2]
  double phi_d;    // (-pi, pi]; 0 at d = pole
};

// The rotation Ry(-theta_h) Rz(-phi_h) taking h to the pole, from the components of s = w_i + w_r (any
// positive multiple of h): cos/sin of phi_h (c, sn) and of theta_h (ct, st); |s| returned in len.
struct HalfAngleFrame {
  double c = 1, sn = 0, ct = 1, st = 0, len = 0;
};
inline HalfAngleFrame half_angle_frame(double sx, double sy, double sz) {
  HalfAngleFrame f;
  const double rho2 = sx * sx + sy * sy, len2 = rho2 + sz * sz;
  if (!(len2 >= DBL_MIN)) return f;  // w_i = -w_r: fallback h = n (identity frame), len = 0
  const double rho = std::sqrt(rho2);
  f.len = std::sqrt(len2);
  if (rho > 0.0) {
    f.c = sx / rho;
    f.sn = sy / rho;
  }
  f.ct = sz / f.len;
  f.st = rho / f.len;
  return f;
}

// h and d (unit to rounding) of one pair.
inline void half_diff_from_pair(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr, Eigen::Vector3d& h,
                                Eigen::Vector3d& d) {
  const Eigen::Vector3d s = wi + wr, m = wi - wr;
  const HalfAngleFrame f = half_angle_frame(s.x(), s.y(), s.z());
  h = f.len > 0.0 ? Eigen::Vector3d(f.st * f.c, f.st * f.sn, f.ct) : Eigen::Vector3d(0, 0, 1);
  const double xp = f.c * m.x() + f.sn * m.y(), yp = -f.sn * m.x() + f.c * m.y();
  d = Eigen::Vector3d(0.5 * (f.ct * xp - f.st * m.z()), 0.5 * yp, 0.5 * f.len);
}

// (w_i, w_r) from h and d: w_i = R^T d, w_r = R^T (-d_x, -d_y, d_z), R^T = Rz(phi_h) Ry(theta_h).
inline void pair_from_half_diff(const Eigen::Vector3d& h, const Eigen::Vector3d& d, Eigen::Vector3d& wi,
                                Eigen::Vector3d& wr) {
  const HalfAngleFrame f = half_angle_frame(h.x(), h.y(), h.z());
  const auto back = [&](double x, double y, double z) {
    const double X = f.ct * x + f.st * z, Z = -f.st * x + f.ct * z;
    return Eigen::Vector3d(f.c * X - f.sn * y, f.sn * X + f.c * y, Z);
  };
  wi = back(d.x(), d.y(), d.z());
  wr = back(-d.x(), -d.y(), d.z());
}

// Angles (theta, phi) of a vector with atan2; phi = 0 on the pole.
inline double polar_angle(double x, double y, double z) { return std::atan2(std::sqrt(x * x + y * y), z); }
inline double azimuth_angle(double x, double y) { return (x == 0.0 && y == 0.0) ? 0.0 : std::atan2(y, x); }

inline HalfAngleCoords half_angle_from_pair(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) {
  Eigen::Vector3d h, d;
  half_diff_from_pair(wi, wr, h, d);
  return {polar_angle(h.x(), h.y(), h.z()), azimuth_angle(h.x(), h.y()), polar_angle(d.x(), d.y(), d.z()),
          azimuth_angle(d.x(), d.y())};
}

inline void pair_from_half_angle(const HalfAngleCoords& a, Eigen::Vector3d& wi, Eigen::Vector3d& wr) {
  const double sth = std::sin(a.theta_h), std_ = std::sin(a.theta_d);
  const Eigen::Vector3d h(sth * std::cos(a.phi_h), sth * std::sin(a.phi_h), std::cos(a.theta_h));
  const Eigen::Vector3d d(std_ * std::cos(a.phi_d), std_ * std::sin(a.phi_d), std::cos(a.theta_d));
  pair_from_half_diff(h, d, wi, wr);
}

// Batch forms (rows are pairs). Angle matrices have the columns theta_h, phi_h, theta_d, phi_d.
using HalfAngleMatrix = Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>;
// ArgumentError when wi and wr (or h and d) have different row counts.
void half_diff_from_pairs(const RowMatrix3d& wi, const RowMatrix3d& wr, RowMatrix3d& h, RowMatrix3d& d);
void pairs_from_half_diff(const RowMatrix3d& h, const RowMatrix3d& d, RowMatrix3d& wi, RowMatrix3d& wr);
HalfAngleMatrix half_angles_from_pairs(const RowMatrix3d& wi, const RowMatrix3d& wr);
void pairs_from_half_angles(const HalfAngleMatrix& angles, RowMatrix3d& wi, RowMatrix3d& wr);

}  // namespace icobrdf
