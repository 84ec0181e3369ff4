#pragma once
// The principal axes and widths of a specular lobe around h = n, used to stretch the h grid of anisotropic
// half-angle factors (icobrdf/core/models/half_angle_factors.hpp) so that an elliptical lobe becomes circular.
//
// Probe: p(h) = sum over channels of f(h, h) (w_i = w_r = h, theta_d = 0: the lobe seen along its own axis).
// Along kLobeAzimuths azimuths psi the probe is marched outwards in theta_h (t^2 steps, up to kLobeMaxTheta)
// to the first point where it falls to half of p(n); the slope radius r(psi) = tan(theta_h) there is
// interpolated linearly between the two samples. The ellipse x^T A x = 1 through the points
// (r cos psi, r sin psi) is fitted by linear least squares (A symmetric, three unknowns); its axes are the
// eigenvectors of A and its half-maximum widths 1 / sqrt(eigenvalues). For GGX and Beckmann the half-maximum
// contour of D is exactly such an ellipse with axes along x and y and widths proportional to (alpha_x,
// alpha_y); Smith masking and Fresnel at theta_d = 0 bend it by under 1% at alpha <= 0.3.
//
// Not found (identity stretch: the caller keeps the plain grid) when p(n) is not positive and finite, when an
// azimuth never falls to half within kLobeMaxTheta (a broad or non-peaked function), when A is not positive
// definite, or when the radii deviate from the ellipse by more than kLobeEllipseTolerance (rms, relative).
#include <string>

#include "icobrdf/core/fit/half_angle_fit.hpp"
#include "icobrdf/core/models/half_angle_factors.hpp"

namespace icobrdf {

inline constexpr int kLobeAzimuths = 32;
inline constexpr int kLobeSteps = 400;                    // samples per azimuth
inline constexpr double kLobeMaxTheta = 80.0 * M_PI / 180;  // beyond it p(h) is mostly masking, not the lobe
// A lobe whose half-maximum radii leave the fitted ellipse by more than this (rms, relative) is not elliptical
// enough for a linear stretch to make it circular.
inline constexpr double kLobeEllipseTolerance = 0.1;

struct LobeAxes {
  bool found = false;
  std::string why;       // when not found
  double axis = 0.0;     // angle of the wide axis from x [rad], in (-pi/2, pi/2]
  double wide = 0.0;     // half-maximum slope radius along the wide axis
  double narrow = 0.0;   // along the narrow axis (perpendicular)
  double residual = 0.0; // rms relative deviation of r(psi) from the ellipse
  double ratio() const { return narrow > 0.0 ? wide / narrow : 1.0; }
};

LobeAxes estimate_lobe_axes(const PairSampler& sampler, int channels);

}  // namespace icobrdf
