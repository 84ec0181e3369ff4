#pragma once
// Particulate-surface models of the Lommel-Seeliger / Hapke family (isotropic scatterers).
// w = single-scattering albedo in [0, 1]; mu = cos(theta) = z.
//
// Lommel-Seeliger (single scattering only):  f = w / (4 pi (mu_i + mu_r)).
//   Directional albedo (w/2)(1 - mu_i ln((1 + mu_i)/mu_i)): w (1 - ln 2)/2 at normal incidence, w/2 at grazing.
// Hapke, isotropic variant: isotropic single scattering (phase function 1), multiple scattering treated
// exactly for a semi-infinite medium of isotropic scatterers, no opposition surge, no macroscopic
// roughness (Hapke 1981 eq. with p = 1, B = 0, with Chandrasekhar's exact H function instead of Hapke's
// approximations of it):
//   f = w / (4 pi) H(mu_i) H(mu_r) / (mu_i + mu_r).
//   Directional albedo exactly 1 - sqrt(1 - w) H(mu_i) (= 1 for w = 1: conservative).
// Both diverge as 1/(mu_i + mu_r) at double grazing; mu_i + mu_r is floored at kGrazingCosFloor.
#include <Eigen/Core>

#include <vector>

#include "icobrdf/core/models/brdf_model.hpp"

namespace icobrdf {

// Chandrasekhar's H function for isotropic scattering with single-scattering albedo w, the solution of
//   1/H(mu) = sqrt(1 - w) + (w/2) integral_0^1 mu' H(mu') / (mu + mu') dmu'.
// Solved by Nystrom on Gauss-Legendre panels graded geometrically towards mu = 0 (208 nodes), then
// tabulated on a grid uniform in sqrt(mu) and interpolated with 4-point Lagrange: operator() is accurate
// to 1e-8 (worst near mu = 0, where H ~ 1 + c mu ln mu), exact() evaluates the Nystrom formula directly
// (~1e-13; tests/core/models/test_brdf_hapke.cpp).
class ChandrasekharH {
 public:
  explicit ChandrasekharH(double w);
  double operator()(double mu) const;  // mu clamped to [0, 1]
  double exact(double mu) const;
  double w() const { return w_; }

 private:
  double w_, s_;
  std::vector<double> nodes_, weights_, h_nodes_, table_;
};

class LommelSeeligerModel final : public ScalarBrdfModel {
 public:
  explicit LommelSeeligerModel(double w) : w_(w) {}
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  std::string spec() const override;

 private:
  double w_;
};

class HapkeModel final : public ScalarBrdfModel {
 public:
  explicit HapkeModel(double w) : w_(w), h_(w) {}
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  std::string spec() const override;
  const ChandrasekharH& h_function() const { return h_; }

 private:
  double w_;
  ChandrasekharH h_;
};

}  // namespace icobrdf
