#pragma once
// The BRDF models of land remote sensing, as published, in the library's conventions (SPEC-NOTES):
// w_i towards the light (the sun), w_r towards the viewer, f in 1/sr. Remote sensing writes the
// bidirectional reflectance factor BRF = pi f, the solar zenith sza = theta_i, the view zenith vza = theta_r and
// the relative azimuth raa = phi_r - phi_i; raa = 0 puts the viewer on the sun's side, where the hot spot
// (w_r = w_i, phase angle xi = 0) lies, and raa = 180 deg is forward scattering. The phase angle is
// cos(xi) = w_i . w_r = cos(sza) cos(vza) + sin(sza) sin(vza) cos(raa).
//
// Kernel-driven (MODIS MCD43; Lucht, Schaaf & Strahler 2000, IEEE TGRS 38(2), eqs. 38-46):
//   f = (iso + vol K_vol + geo K_geo) / pi, with
//   Ross-Thick  K = ((pi/2 - xi) cos(xi) + sin(xi)) / (cos(sza) + cos(vza)) - pi/4
//   Ross-Thin   K = ((pi/2 - xi) cos(xi) + sin(xi)) / (cos(sza) cos(vza)) - pi/2
//   Li-Sparse-R K = O - sec(sza') - sec(vza') + (1 + cos(xi')) sec(sza') sec(vza') / 2
//   Li-Dense-R  K = (1 + cos(xi')) sec(sza') sec(vza') / (sec(sza') + sec(vza') - O) - 2
//   O = (t - sin(t) cos(t)) (sec(sza') + sec(vza')) / pi,  cos(t) = (h/b) sqrt(D^2 + (tan(sza') tan(vza') sin(raa))^2)
//   / (sec(sza') + sec(vza')) clamped to [-1, 1], D^2 = tan^2(sza') + tan^2(vza') - 2 tan(sza') tan(vza') cos(raa),
//   primes: tan(theta') = (b/r) tan(theta); MODIS's crown shape h/b = 2, b/r = 1 (so theta' = theta).
// All four kernels are symmetric in (sza, vza) at a given raa: the model is reciprocal for any weights. Its
// white-sky albedo is iso + vol H_vol + geo H_geo with the kernels' bihemispherical integrals (Ross-Thick
// 0.189184, Li-Sparse-R -1.377622 in the MODIS BRDF/albedo ATBD; tests/core/models/test_kernel_models.cpp
// integrates them). The kernels grow as sec(theta) towards grazing: every cos(theta) is floored at
// kGrazingCosFloor. The Li kernels fall as -sec(theta) towards grazing, so f < 0 near the horizon for any
// geo > 0 (MODIS inverts views within 70 degrees or so): the registry's default has geo = 0. Weights may be
// negative; the model does not check f >= 0, and its albedo need not be <= 1.
//
// RPV (Rahman, Pinty & Verstraete 1993, JGR 98(D11), eqs. 4-8), with the Henyey-Greenstein phase function:
//   BRF = rho0 (cos(sza) cos(vza))^(k-1) / (cos(sza) + cos(vza))^(1-k) F(xi) (1 + (1 - rhoc) / (1 + G)),
//   F = (1 - Theta^2) / (1 + 2 Theta cos(xi) + Theta^2)^(3/2),
//   G = sqrt(tan^2(sza) + tan^2(vza) - 2 tan(sza) tan(vza) cos(raa)) (0 at the hot spot),
// Theta < 0 scatters backwards (towards the hot spot), k < 1 makes the surface bowl-shaped (brighter at
// grazing); rhoc is the hot-spot parameter (rhoc = rho0 in the three-parameter form). Reciprocal (every factor
// is symmetric in the two directions). For k < 1 the cosines are floored at kGrazingCosFloor.
//
// Walthall, in the reciprocal form of Nilson & Kuusk (1989, Remote Sens. Environ. 27, eq. 11) of Walthall et al.
// (1985), angles in radians:
//   BRF = a (sza^2 + vza^2) + b sza^2 vza^2 + c sza vza cos(raa) + d.
// Walthall et al.'s own form (BRF = a vza^2 + b vza cos(raa) + c at one solar zenith) is not reciprocal; this
// one is, and is the one its authors' successors fit to multi-angle data.
#include <string>

#include "icobrdf/core/models/brdf_model.hpp"

namespace icobrdf {

enum class VolumeKernel { RossThick, RossThin };     // names "thick", "thin"
enum class GeometricKernel { LiSparseR, LiDenseR };  // names "sparse", "dense"

// The kernels at one pair (both directions on or above the horizon, unit vectors).
double ross_kernel(VolumeKernel kind, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr);
double li_kernel(GeometricKernel kind, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr);

class RossLiModel final : public ScalarBrdfModel {
 public:
  RossLiModel(double iso, double vol, double geo, VolumeKernel volume = VolumeKernel::RossThick,
              GeometricKernel geometric = GeometricKernel::LiSparseR)
      : iso_(iso), vol_(vol), geo_(geo), volume_(volume), geometric_(geometric) {}
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  std::string spec() const override;
  double iso() const { return iso_; }
  double vol() const { return vol_; }
  double geo() const { return geo_; }
  VolumeKernel volume() const { return volume_; }
  GeometricKernel geometric() const { return geometric_; }

 private:
  double iso_, vol_, geo_;
  VolumeKernel volume_;
  GeometricKernel geometric_;
};

class RpvModel final : public ScalarBrdfModel {
 public:
  RpvModel(double rho0, double k, double theta, double rhoc) : rho0_(rho0), k_(k), theta_(theta), rhoc_(rhoc) {}
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  std::string spec() const override;

 private:
  double rho0_, k_, theta_, rhoc_;
};

class WalthallModel final : public ScalarBrdfModel {
 public:
  WalthallModel(double a, double b, double c, double d) : a_(a), b_(b), c_(c), d_(d) {}
  double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const override;
  std::string spec() const override;

 private:
  double a_, b_, c_, d_;
};

}  // namespace icobrdf
