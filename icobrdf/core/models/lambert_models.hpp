#pragma once
// Diffuse-type models: Lambert, Minnaert (K&vD 1998 eq. 35) and the qualitative Oren-Nayar model.
// mu = cos(theta) = z. All are reciprocal and isotropic.
#include "icobrdf/core/models/brdf_model.hpp"

namespace icobrdf {

// f = albedo / pi. Directional albedo = albedo at every incidence.
class LambertModel final : public ScalarBrdfModel {
 public:
  explicit LambertModel(double albedo = 1.0) : albedo_(albedo) {}
  double value(const Eigen::Vector3d&, const Eigen::Vector3d&) const override { return albedo_ / M_PI; }
  std::string spec() const override;
  double albedo() const { return albedo_; }

 private:
  double albedo_;
};

// f = (k + 1)/(2 pi) (mu_i mu_r)^(k - 1), k >= 0 (integer or real).
// Directional albedo: integral of f mu_r dOmega_r = mu_i^(k - 1), so <= 1 (physical) exactly for k >= 1,
// with equality at normal incidence; k = 1 is Lambert 1/pi. For k < 1, f diverges at grazing: each mu is
// floored at kGrazingCosFloor in that case. For k >= 1 f is a bounded polynomial-like function (no floor).
class MinnaertModel final : public ScalarBrdfModel {
 public:
  explicit MinnaertModel(double k);
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  std::string spec() const override;
  double k() const { return k_; }

 private:
  double k_, c_;
};

// Oren-Nayar (1994) qualitative model, sigma = standard deviation of the facet slope angle:
//   f = albedo/pi (A + B max(0, cos(phi_i - phi_r)) sin(alpha) tan(beta)),
//   alpha = max(theta_i, theta_r), beta = min(theta_i, theta_r),
//   A = 1 - 0.5 s^2/(s^2 + 0.33), B = 0.45 s^2/(s^2 + 0.09), s = sigma in radians.
// In vectors, cos(phi_i - phi_r) sin(alpha) tan(beta) = (x_i x_r + y_i y_r) / max(mu_i, mu_r), which is
// what is evaluated (exactly symmetric; no trigonometry). It diverges at double grazing in the
// backscatter half (phi_i = phi_r): max(mu_i, mu_r) is floored at kGrazingCosFloor. Not exactly energy
// conserving: see docs/models.md for the measured albedo.
class OrenNayarModel final : public ScalarBrdfModel {
 public:
  OrenNayarModel(double sigma_deg, double albedo);
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  std::string spec() const override;

 private:
  double sigma_deg_, albedo_, a_, b_;
};

}  // namespace icobrdf
