#pragma once
// The MODIS BRDF/albedo ATBD's approximation of the kernels' albedo integrals (Lucht, Schaaf & Strahler 2000,
// IEEE TGRS 38(2), 977-998, Table 1; the same constants drive the MCD43 albedo products): for the kernel K (f = K/pi)
//   black-sky  h(s) ~ g0 + g1 s^2 + g2 s^3   (s the solar zenith in radians)
//   white-sky  H    = the bihemispherical integral, printed to 6 decimals.
// The polynomial is a fit, not the integral: against the integral of the kernels themselves
// (icobrdf/core/models/albedo_quadrature.hpp; docs/albedo.md tabulates both) it is off by up to 0.018
// for Ross-Thick between 0 and 70 degrees (0.0135 at nadir, 0.075 at 80) and by up to 0.0061 for Li-Sparse-R
// between 0 and 80 degrees.
// The model ross-li:iso=..,vol=..,geo=.. (Ross-Thick, Li-Sparse-R) then has the ATBD black-sky albedo
// iso + vol h_vol(s) + geo h_geo(s), and the white-sky albedo iso + vol H_vol + geo H_geo.
#include <optional>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/models/kernel_models.hpp"

namespace icobrdf {

struct KernelAlbedoPolynomial {
  double g0, g1, g2;  // black-sky h(s) = g0 + g1 s^2 + g2 s^3
  double white_sky;   // H
};

inline constexpr KernelAlbedoPolynomial kAtbdIsotropic{1.0, 0.0, 0.0, 1.0};
inline constexpr KernelAlbedoPolynomial kAtbdRossThick{-0.007574, -0.070987, 0.307588, 0.189184};
inline constexpr KernelAlbedoPolynomial kAtbdLiSparseR{-1.284909, -0.166314, 0.041840, -1.377622};

inline double atbd_black_sky(const KernelAlbedoPolynomial& p, double s) { return p.g0 + p.g1 * s * s + p.g2 * s * s * s; }

// The ATBD's black-sky albedo of `model` at solar zenith s [rad] when the model is a ross-li with the ATBD's
// kernels (Ross-Thick, Li-Sparse-R); nullopt for any other model (the ATBD tabulates no other).
inline std::optional<double> atbd_black_sky_of(const BrdfModel& model, double s) {
  const auto* m = dynamic_cast<const RossLiModel*>(&model);
  if (!m || m->volume() != VolumeKernel::RossThick || m->geometric() != GeometricKernel::LiSparseR) return std::nullopt;
  return m->iso() + m->vol() * atbd_black_sky(kAtbdRossThick, s) + m->geo() * atbd_black_sky(kAtbdLiSparseR, s);
}

// The same for the white-sky albedo.
inline std::optional<double> atbd_white_sky_of(const BrdfModel& model) {
  const auto* m = dynamic_cast<const RossLiModel*>(&model);
  if (!m || m->volume() != VolumeKernel::RossThick || m->geometric() != GeometricKernel::LiSparseR) return std::nullopt;
  return m->iso() + m->vol() * kAtbdRossThick.white_sky + m->geo() * kAtbdLiSparseR.white_sky;
}

}  // namespace icobrdf
