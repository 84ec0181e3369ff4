#pragma once
// Sampling GGX's distribution of visible normals (Heitz 2018, "Sampling the GGX Distribution of Visible
// Normals", JCGT 7(4)), the importance sampling of a GGX microfacet lobe (icobrdf/core/models/microfacet.hpp).
//
// Frame: the distribution's tangent frame (x along alpha_x), unit vectors, +z the normal; w_i points away
// from the surface. For w_i with z >= 0 the visible normals have the density [1/sr, over h]
//   D_wi(h) = G1(w_i) max(0, w_i . h) D(h) / w_i,z = max(0, w_i . h) D(h) / (w_i,z + L(w_i)),
// L = w_z Lambda (smith_z_lambda), which stays finite at grazing (w_i,z = 0: density max(0, w_i . h) D / L).
// It integrates to 1 over the hemisphere of h. Reflecting w_i about h gives w_r = 2 (w_i . h) h - w_i with the
// density D_wi(h) / (4 w_i . h) over w_r; w_r can fall below the horizon (z < 0): the caller rejects it.
// With f the microfacet BRDF of height-correlated Smith masking, the weight f cos(theta_r) / pdf(w_r) is
// F(w_i . h) G2(w_i, w_r) / G1(w_i), at most F.
// Map: (u1, u2) in [0, 1)^2 -> h, continuous and one-to-one onto the visible hemisphere of normals.
// Accuracy: rounding only (the map and the density are closed forms).
#include <Eigen/Core>

namespace icobrdf {

// The sampled microfacet normal h (unit, h_z >= 0) for w_i (unit, z >= 0) and widths alpha_x, alpha_y > 0.
Eigen::Vector3d sample_ggx_visible_normal(const Eigen::Vector3d& wi, double alpha_x, double alpha_y, double u1,
                                          double u2);

// D_wi(h) [1/sr over h]; 0 for h_z <= 0 or w_i . h <= 0.
double ggx_visible_normal_pdf(const Eigen::Vector3d& wi, const Eigen::Vector3d& h, double alpha_x, double alpha_y);

}  // namespace icobrdf
