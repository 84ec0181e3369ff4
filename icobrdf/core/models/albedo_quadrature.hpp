#pragma once
// Albedos of a BRDF by product quadrature, in the library's conventions (docs/conventions.md: w_i towards the
// light, f in 1/sr), the quantities of land remote sensing:
//   black-sky (directional-hemispherical) albedo at solar zenith s:  a(s) = int_{view hemisphere} f(w_s, w_v) cos(theta_v) dw_v
//   white-sky (bihemispherical, isotropic illumination):             A = (1/pi) int int f cos(theta_i) cos(theta_v) dw_i dw_v
//                                                                      = 2 int_0^{pi/2} a(s) cos(s) sin(s) ds
// For an anisotropic model (BrdfModel::is_isotropic false) a(s) is the mean over the sun's azimuth (a surface
// of random orientation about its normal), by the trapezoid rule over `sun_azimuths` equally spaced azimuths;
// an isotropic model takes the sun at azimuth 0 alone. Delta parts (mirror, retroreflector) add their weight to
// every a(s) and to A (g = weight x delta: its directional albedo is the weight at every incidence).
//
// The rule (AlbedoRule), per sun direction w_s = (theta_s, phi_s), mu = cos(theta_v), psi = phi_v - phi_s:
//   mu:  Gauss-Legendre on the two panels [0, cos(theta_s)] and [cos(theta_s), 1], `polar_nodes` each (one panel
//        of 2 x polar_nodes when cos(theta_s) is 0 or 1);
//   psi: Gauss-Legendre on the two half turns [0, pi] and [pi, 2 pi], `azimuth_nodes` each;
// so that the panel edges pass through the hot spot (w_v = w_s) and the mirror direction, where measured and
// modelled BRDFs have their peaks and kinks (the Li kernels' cone at the hot spot). White-sky: Gauss-Legendre in
// mu_s = cos(s) on [0, 1], `sun_polar_nodes` nodes, of 2 mu_s a(mu_s).
//
// Accuracy, measured (tests/core/models/test_albedo_quadrature.cpp; docs/albedo.md), default rule:
// smooth BRDFs to 1e-12 (Lambert exact; Minnaert and Lommel-Seeliger against their closed forms; Phong n = 20 at
// normal incidence; Lommel-Seeliger 4.4e-8 with the sun 0.1 degree above the horizon, near its pole); the
// Ross-Thick kernel's black-sky integrals to 9e-12 and the Li-Sparse-R kernel's (with its kink where the crowns'
// shadows start to overlap) to 3.9e-6 of an adaptive quadrature; GGX alpha 0.05 to 3e-6, alpha 0.02 to 9e-4
// (narrow lobes need more nodes).
// Cost: 2 polar_nodes x 2 azimuth_nodes (12,288 by default) evaluations per sun direction.
#include <Eigen/Core>

#include "icobrdf/core/grid/row_matrix.hpp"
#include "icobrdf/core/models/brdf_model.hpp"

namespace icobrdf {

struct AlbedoRule {
  int polar_nodes = 48;      // Gauss-Legendre nodes per panel of cos(theta_v) (two panels, split at cos(theta_s))
  int azimuth_nodes = 64;    // Gauss-Legendre nodes per half turn of the view azimuth relative to the sun
  int sun_polar_nodes = 48;  // white-sky: Gauss-Legendre nodes in cos(theta_s) on [0, 1]
  int sun_azimuths = 16;     // anisotropic models: sun azimuths averaged over (trapezoid on [0, 2 pi))
};

// Checks the rule's counts (each >= 1, at most 4096); ArgumentError naming the count otherwise.
void check_albedo_rule(const AlbedoRule& rule);

// The view-hemisphere nodes at the sun direction (theta_s, phi_s) [rad], theta_s in [0, pi/2]: directions
// (n x 3, unit vectors) and weights (n) with sum_k weights(k) f(w_s, directions.row(k)) = a(theta_s) for a
// smooth f; the weights include cos(theta_v) and sum to pi (the cosine-weighted solid angle of the hemisphere).
struct ViewNodes {
  RowMatrix3d directions;
  Eigen::VectorXd weights;
};
ViewNodes black_sky_nodes(double theta_s, double phi_s, const AlbedoRule& rule);

// a(theta_s) per channel: rows = theta_s [rad] (each in [0, pi/2]), columns = model.channels(). ArgumentError for
// a zenith out of range. Values are as the model gives them: NaN where it has none (the caller checks).
Eigen::MatrixXd black_sky_albedo(const BrdfModel& model, const Eigen::VectorXd& theta_s, const AlbedoRule& rule = {});
// A per channel (1 x channels).
Eigen::RowVectorXd white_sky_albedo(const BrdfModel& model, const AlbedoRule& rule = {});

}  // namespace icobrdf
