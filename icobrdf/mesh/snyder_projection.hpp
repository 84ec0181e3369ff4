#pragma once
// Snyder's equal-area projection of one spherical icosahedron face onto a planar equilateral triangle.
//
// Planar coordinates are the barycentric coordinates (l0, l1, l2), l0 + l1 + l2 = 1, of the planar face
// with corners P0, P1, P2 matching the spherical corners V0, V1, V2 (counter-clockwise seen from outside).
// The planar face is scaled so that its area equals the solid angle of the spherical face, 4 pi / 20 sr;
// planar area is then solid angle: a planar region of area A maps onto a spherical region of A sr.
//
// Construction (Snyder 1992): the face is split into 6 right spherical triangles C M V (C the face centre,
// M an edge midpoint with the right angle, V a corner); the planar face likewise. For P in C M V with
// azimuth Az at C measured from CM (0 <= Az <= 60 deg) and arc distance z = CP: the great circle from C at
// Az meets MV at Q with MQ = b, tan b = sin a tan Az (a = arc CM), cos q = cos a cos b (q = arc CQ), and
// the area of C M Q is E = 2 atan(tan(a/2) tan(b/2)). The planar image has azimuth Az' with
// r^2 tan(Az') / 2 = E (r = planar inradius) and radius rho = (r / cos Az') sin(z/2) / sin(q/2).
// Equal area: the planar and spherical sectors from C to Q have equal areas for every Az, and along each
// ray the map sends the spherical cap area 2 sin^2(z/2) dAz to the planar rho^2/2 dAz'.
//
// Both directions are closed-form (no iteration):
//   forward: tan Az from the tangent components, b, E, Az', then x = rho cos Az' = r sin(z/2)/sin(q/2)
//            (sin(z/2) = |P - C| / 2, computed from the tangent components without cancellation),
//            y = x tan Az' (see forward_xy for the form with two square roots and two divisions).
//   inverse: E = r^2 tan(Az')/2 -> tan(b/2) = tan(E/2)/tan(a/2) -> tan Az = tan b / sin a,
//            sin(z/2) = x sin(q/2) / r.
// The map is continuous across the 6 sub-triangle boundaries and across face edges (adjacent faces agree
// on their common edge), but only piecewise smooth: its derivative jumps on the sub-triangle boundaries.
// Round trips (forward o inverse, inverse o forward) are exact to a few 1e-16 (tested to 1e-14).
//
// Sub-triangles are indexed 0..5 by the ordering of the barycentric coordinates: corner k = argmax
// (first index on ties), midpoint m = argmin of the other two (the later one on ties); index 2k + t with
// t = 0 when m = k+1 (mod 3), else 1. On the sphere the same ordering of d . V_k selects the same
// sub-triangle (the boundaries are the face's mirror planes, with normals V_a - V_b).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>

namespace icobrdf {

class SnyderProjection {
 public:
  // Solid angle of one icosahedron face = area of the planar face [sr].
  static constexpr double kFaceArea = 4.0 * M_PI / 20.0;

  // corners: the unit corner vectors of a face of the regular icosahedron, counter-clockwise seen from
  // outside (the constants a and r are those of the regular icosahedron).
  explicit SnyderProjection(const std::array<Eigen::Vector3d, 3>& corners);

  // Sub-triangle (0..5) of barycentric coordinates, or of the corner dot products (d . V_k).
  static int sub_triangle(double g0, double g1, double g2) {
    // k = first argmax; m = argmin of the other two (the later one on ties); t = (m == k+1 mod 3) ? 0 : 1,
    // i.e. t = !(g[k+1] < g[k+2]). Branch-free: four comparisons index a table (unreachable entries 0).
    static constexpr signed char kTable[16] = {1, 3, 0, 3, 0, 0, 5, 4, 1, 2, 0, 0, 0, 0, 0, 0};
    const int idx = (g1 > g0) | ((g2 > g0) << 1) | ((g2 > g1) << 2) | ((g0 > g2) << 3);
    return kTable[idx];
  }
  static int sub_triangle(const Eigen::Vector3d& g) { return sub_triangle(g[0], g[1], g[2]); }

  // atan(x) for 0 <= x <= 0.07 by its Taylor series through x^15 (remainder < 1e-21 relative); the forward
  // map only needs x = tan(a/2) tan(b/2) <= tan(a/2) tan(b_max/2) = 0.0524 (b_max at Az = 60 deg).
  static double atan_small(double x) {
    const double x2 = x * x;
    return x * (1.0 + x2 * (-1.0 / 3 + x2 * (1.0 / 5 + x2 * (-1.0 / 7 + x2 * (1.0 / 9 + x2 * (-1.0 / 11 + x2 * (1.0 / 13 - x2 / 15)))))));
  }

  // Unit direction (on or near the face) -> planar barycentric coordinates.
  Eigen::Vector3d forward(const Eigen::Vector3d& d) const {
    const int s = sub_triangle(d.dot(v_[0]), d.dot(v_[1]), d.dot(v_[2]));
    double x, y;
    forward_xy(d, s, x, y);
    const Frame& f = frames_[s];
    return Eigen::Vector3d(1.0 / 3.0 + x * f.gx[0] + y * f.gy[0], 1.0 / 3.0 + x * f.gx[1] + y * f.gy[1],
                           1.0 / 3.0 + x * f.gx[2] + y * f.gy[2]);
  }

  // Planar barycentric coordinates -> unit direction, using sub-triangle `sub` (continuous extension
  // across its boundaries); the one-argument form picks the sub-triangle from the ordering.
  Eigen::Vector3d inverse(const Eigen::Vector3d& bary, int sub) const;
  Eigen::Vector3d inverse(const Eigen::Vector3d& bary) const { return inverse(bary, sub_triangle(bary)); }

  const Eigen::Vector3d& centre() const { return c_; }
  const Eigen::Vector3d& corner(int k) const { return v_[k]; }
  double inradius() const { return r_; }
  // Largest argument tan(a/2) tan(b/2) of the forward map's atan (at Az = 60 deg).
  double atan_argument_max() const { return targ_max_; }
  double arc_centre_midpoint() const { return a_; }  // a = arc CM [rad]

  // Frame of sub-triangle s, in the sub-triangle's planar coordinates (x along C'M', y towards the corner):
  //   l_k = 1/3 + x gx[k] + y gy[k];  x = sum_k l_k hx[k], y = sum_k l_k hy[k].
  struct Frame {
    Eigen::Vector3d u, w;  // sphere: unit tangents at C towards M and (orthogonal) towards V
    double gx[3], gy[3], hx[3], hy[3];
  };
  const Frame& frame(int s) const { return frames_[s]; }

  // Forward map inside sub-triangle s: planar frame coordinates (x, y) of unit direction d.
  // With du = d.u, dw = d.w (tangent components), dc = d.C and S = sqrt(du^2 + sin^2(a) dw^2):
  //   sec b = S / du, tan(b/2) = sin(a) dw / (du + S), sin^2(q/2) = (S - cos(a) du) / (2 S),
  //   x = r sin(z/2) / sin(q/2) = r sqrt(chord^2 S / (2 (S - cos(a) du))), chord^2 = (1-dc)^2 + du^2 + dw^2,
  //   y = x tan Az' = x 2 E / r^2, E = 2 atan(tan(a/2) tan(b/2)).
  // Two square roots and two divisions; no cancellation (S - cos(a) du >= (1 - cos a) du).
  void forward_xy(const Eigen::Vector3d& d, int s, double& x, double& y) const {
    const Frame& f = frames_[s];
    const double dc = d.dot(c_), du = d.dot(f.u), dw0 = d.dot(f.w);
    const double dw = dw0 > 0 ? dw0 : 0.0;  // rounding just outside the sub-triangle
    const double sdw = sin_a_ * dw;
    const double big_s = std::sqrt(du * du + sdw * sdw);
    const double den = du + big_s;
    if (!(den > 0.0)) {  // d at the face centre (du = dw = 0)
      x = 0.0;
      y = 0.0;
      return;
    }
    // tan(a/2) tan(b/2), clamped to its value at Az = 60 deg: beyond it only by rounding (in particular
    // next to the centre, where du and dw are rounding-sized and den may be tiny).
    const double targ = std::min(tan_half_a_ * sdw / den, targ_max_);
    const double e = 2.0 * atan_small(targ);  // area of C M Q
    const double one_minus_dc = 1.0 - dc;
    const double chord2 = one_minus_dc * one_minus_dc + du * du + dw0 * dw0;  // (2 sin(z/2))^2
    x = r_ * std::sqrt(chord2 * big_s / (2.0 * (big_s - cos_a_ * du)));
    y = x * (2.0 * e / (r_ * r_));
  }

 private:
  Eigen::Vector3d c_;
  std::array<Eigen::Vector3d, 3> v_;
  std::array<Frame, 6> frames_;
  double a_ = 0, sin_a_ = 0, cos_a_ = 0, tan_half_a_ = 0, r_ = 0, targ_max_ = 0;
};

}  // namespace icobrdf
