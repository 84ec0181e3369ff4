#pragma once
// Cosine-lobe models: reciprocal Phong, Blinn-Phong, and Lafortune generalized cosine lobes.
// All lobes are clamped at 0 (a negative base gives 0); the exponent n >= 0 may be real.
#include "icobrdf/core/models/brdf_model.hpp"

namespace icobrdf {

// Reciprocal, energy-normalized Phong (Lewis 1994): with cos(a) = w_r . m(w_i), m(w) = (-x, -y, z),
//   f = ks (n + 2)/(2 pi) max(0, cos a)^n.
// cos a = -x_i x_r - y_i y_r + z_i z_r is symmetric, so f is reciprocal. The factor (n + 2)/(2 pi) makes
// the directional albedo exactly ks at normal incidence (integral of cos^n theta cos theta dOmega =
// 2 pi/(n + 2)); at oblique incidence part of the lobe falls below the horizon and the albedo is smaller.
class PhongModel final : public ScalarBrdfModel {
 public:
  PhongModel(double n, double ks);
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  std::string spec() const override;

 private:
  double n_, ks_, c_;
};

// Reciprocal Blinn-Phong: h = (w_i + w_r)/|w_i + w_r|,  f = ks N(n) h_z^n, normalized so that the
// directional albedo at normal incidence is exactly ks (h_z = cos(theta_r / 2) there):
//   1/N(n) = integral of cos^n(theta/2) cos(theta) dOmega = 8 pi (n + 2^(-n/2)) / ((n + 2)(n + 4)).
// (n = 0: pi; large n: N ~ (n + 6)/(8 pi), close to the common approximation (n + 8)/(8 pi).)
class BlinnPhongModel final : public ScalarBrdfModel {
 public:
  BlinnPhongModel(double n, double ks);
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  std::string spec() const override;
  static double normalization(double n);

 private:
  double n_, ks_, c_;
};

// One Lafortune generalized cosine lobe in the symmetric-matrix form (BRDF lecture 2000, eq. 17):
//   f = max(0, w_i^T Q^T D Q w_r)^n,  D = diag(cx, cy, cz),  Q = rotation about z by `azimuth_deg`.
// M = Q^T D Q is symmetric, so f is reciprocal by construction. cx = cy = -1, cz = 1 is a Phong lobe
// (unnormalized); cx = cy > 0 gives retroreflection; cx < -1 with cz = 1 off-specular peaks.
// Isotropic iff cx = cy. Not normalized: at normal incidence with cx = cy = -cz = -c the albedo is
// 2 pi c^n / (n + 2). Peaks above 10^300 (kMaxLobeDecades) are refused. Scale with a sum weight ("0.1*lafortune:...") for energy balance.
// Largest admissible lobe peak max(|cx|,|cy|,|cz|)^n, in decades (keeps f finite in double precision).
inline constexpr double kMaxLobeDecades = 300.0;

class LafortuneModel final : public ScalarBrdfModel {
 public:
  LafortuneModel(double cx, double cy, double cz, double n, double azimuth_deg);
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  bool is_isotropic() const override { return cx_ == cy_; }
  std::string spec() const override;

 private:
  double cx_, cy_, cz_, n_, azimuth_deg_;
  Eigen::Matrix3d m_;  // Q^T D Q
};

}  // namespace icobrdf
