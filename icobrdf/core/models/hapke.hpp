#pragma once
// Particulate-surface models of the Lommel-Seeliger / Hapke family (isotropic scatterers).
// w = single-scattering albedo in [0, 1]; mu = cos(theta) = z.
//
// Lommel-Seeliger (single scattering only):  f = w / (4 pi (mu_i + mu_r)).
//   Directional albedo (w/2)(1 - mu_i ln((1 + mu_i)/mu_i)): w (1 - ln 2)/2 at normal incidence, w/2 at grazing.
// Hapke (Hapke 2012, "Theory of Reflectance and Emittance Spectroscopy", 2nd ed., eqs. 12.46-12.55; Hapke 1984,
// Icarus 59, for the roughness), with isotropic particles (phase function p = 1), the shadow-hiding opposition
// surge and the macroscopic roughness theta-bar, Chandrasekhar's exact H function in place of Hapke's
// approximation of it:
//   f = r / mu_i,  r = w/(4 pi) mu_ie/(mu_ie + mu_re) [(1 + B(g)) + H(mu_ie) H(mu_re) - 1] S(i, e, psi),
//   B(g) = B0 / (1 + tan(g/2) / h)                       g the phase angle, cos g = w_i . w_r (0 at the hot spot)
// with psi the azimuth between the planes of incidence and emergence (0 on the sun's side, in [0, pi]),
// chi = 1/sqrt(1 + pi tan^2 tb), E1(x) = exp(-2 cot(x) cot(tb)/pi), E2(x) = exp(-cot^2(x) cot^2(tb)/pi),
// eta(x) = chi [cos x + sin x tan(tb) E2(x)/(2 - E1(x))], f(psi) = exp(-2 tan(psi/2)), and for i <= e
//   mu_ie = chi [cos i + sin i tan(tb) (cos(psi) E2(e) + sin^2(psi/2) E2(i)) / (2 - E1(e) - (psi/pi) E1(i))]
//   mu_re = chi [cos e + sin e tan(tb) (E2(e) - sin^2(psi/2) E2(i)) / (2 - E1(e) - (psi/pi) E1(i))]
//   S = mu_re/eta(e) mu_i/eta(i) chi / (1 - f(psi) + f(psi) chi mu_i/eta(i)),
// and for e < i the same with i and e exchanged (the last factor then chi mu_r/eta(e)). tb = 0 gives
// mu_ie = mu_i, mu_re = mu_r, S = 1. mu_i = cos i cancels between r and S, so f is evaluated without dividing
// by it. Reciprocal: f = w/(4 pi) mu_ie mu_re chi [..] / ((mu_ie + mu_re) eta(i) eta(e) (1 - f + f chi mu/eta)),
// with mu/eta of the direction nearer the normal, is symmetric (exchanging i and e exchanges the two branches,
// and mu_ie with mu_re); evaluated from the two directions in a canonical order, exchanging them gives the same
// bits. With B0 = 0 and tb = 0 this is the isotropic variant below, in which multiple scattering is exact for
// a semi-infinite medium of isotropic scatterers: directional albedo 1 - sqrt(1 - w) H(mu_i) (1 for w = 1). The
// surge adds single-scattered light (B0 up to 1 for most regoliths, but the model does not conserve energy for
// B0 > 0); the roughness shadows. Diverges as 1/(mu_ie + mu_re) at double grazing (tb = 0 only), floored at
// kGrazingCosFloor, as are the denominator 2 - E1(e) - (psi/pi) E1(i) (0 for opposite directions on the horizon)
// and S's 1 - f(psi) + f(psi) chi mu/eta (0 for both on the horizon at psi = 0, where f diverges as 1/mu). scripts/derive/hapke_values.py evaluates the formulas independently (numpy).
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
  // theta_bar in degrees, [0, 60]; width h > 0.
  explicit HapkeModel(double w, double b0 = 0.0, double width = 0.05, double theta_bar_deg = 0.0)
      : w_(w), b0_(b0), width_(width), theta_bar_(theta_bar_deg), h_(w) {}
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  std::string spec() const override;
  const ChandrasekharH& h_function() const { return h_; }

 private:
  double w_, b0_, width_, theta_bar_;
  ChandrasekharH h_;
};

}  // namespace icobrdf
