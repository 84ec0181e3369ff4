#pragma once
// RGL tensor-file export: any isotropic BRDF as the RGB measured material of Dupuy & Jakob 2018, the file
// Mitsuba 3's and pbrt-v4's `measured` BSDFs render (layout and evaluation: icobrdf/io/rgl_bsdf.hpp, which
// reads it back).
//
// What is written (float32 unless noted; n_t = RglExportOptions::theta_nodes, R = value_resolution,
// V = vndf_resolution, N = ndf_resolution):
//   description  uint8 [L]              "icobrdf export of SOURCE ..."
//   phi_i        [1]                    0 (isotropic: one azimuth; eval uses phi_m - phi_i)
//   theta_i      [n_t]                  theta_k = acos(1 - k / (n_t - 1)): uniform in cos theta_i from the
//                                       normal to grazing, as the database's own files nearly are (the
//                                       slice at pi/2 computed at pi/2 - kRglGrazingSliceOffset, below)
//   ndf          [2, N]                 D over (u_theta, u_phi), u_theta = sqrt(2 theta / pi): from
//                                       back-scattering, D(w) ~ Y(f(w, w)) cos^2 theta (the microfacet form
//                                       f(w, w) = D(w) F G / (4 cos^2 theta) with F G taken constant; Y the
//                                       luminance 0.2126 R + 0.7152 G + 0.0722 B of 3 channels, the value of 1),
//                                       floored at kRglNdfFloor times its peak, normalized so that the
//                                       projected area of D is 1: integral of D cos theta_m dw_m = 1
//   sigma        [2, N]                 sigma(w_i) = integral of D(m) max(0, w_i . m) dw_m over the
//                                       hemisphere of m (D the ndf table's bilinear interpolant; the azimuth
//                                       integral in closed form, the elevation by the midpoint rule on
//                                       kRglSigmaSubdivisions points per ndf interval); sigma(normal) = 1
//   vndf         [1, n_t, V, V]         per slice, the visible-normal density over (u_theta, u_phi):
//                                       D(m) max(0, w_i . m) u_theta sin theta_m (the last two factors: the
//                                       Jacobian of u -> m up to 2 pi^2), u_phi = azimuth of m relative to w_i
//   luminance    [1, n_t, R, R]         Y of the rgb values (negative values count as 0; a slice without a
//                                       positive value is written uniform), the density Mitsuba samples
//   rgb          [1, n_t, 3, R, R]      v_c(s) = f_c(w_i, w_o) cos theta_o 4 sigma(w_i) / D(m) at the nodes s of the
//                                       sample square, m = the vndf warp of s, w_o = 2 (w_i . m) m - w_i;
//                                       0 where w_o is below the horizon. D and sigma are the tables'
//                                       interpolants and the warp is the one the reader builds from the
//                                       float32 vndf, so that the file's evaluation returns f exactly at
//                                       every node (to float32 rounding).
//   jacobian     uint8 [1]              1
// The forward warp of a node is found by bisection on the reader's inverse warp (both coordinates are
// monotone in it), to kRglWarpBisections halvings.
//
// Accuracy: between nodes the file's f is the bilinear interpolant of v in the sample square times the
// ndf and sigma interpolants (and linear in theta_i between slices); tests/io/test_rgl_export.cpp and
// docs/readers.md give the measured agreement (cosine-weighted relative L2 against the source).
//
// Limits: isotropic sources only (the caller checks isotropy: icobrdf/pipeline/renderer_export.hpp); no delta
// parts; 1 channel (written to R, G and B) or 3 channels. ArgumentError for another channel count or bad
// options; InputError (one line) when the source gives a non-finite value at a node. Nothing is written on
// error (the file is written atomically once every table is complete).
#include <string>

#include "icobrdf/core/models/brdf_model.hpp"

namespace icobrdf {

// The ndf is kept positive (the values divide by it): a floor relative to its peak.
inline constexpr double kRglNdfFloor = 1e-4;
// Midpoint points per ndf interval in the sigma quadrature: D is bilinear per interval and the azimuth
// integral is smooth, so 16 points per interval put the quadrature error far below the float32 tables.
inline constexpr int kRglSigmaSubdivisions = 16;
// The slice at theta_i = pi/2 holds the values just inside the horizon: at cos theta_i = 0 models give their
// z = 0 conventions, not the limit (a height-correlated Smith GGX gives 0 there, its limit is finite), and a
// slice of zeros halved the grazing specular values between the last two slices (GGX alpha 0.3, f0 0.04: 0.146
// cosine relative L2 with the slice at pi/2, 0.046 with it 0.01 rad inside; 8 slices, 32 x 32 values).
inline constexpr double kRglGrazingSliceOffset = 0.01;
// Halvings of the bisection that inverts the warp: 2^-40 of the unit square, far below the float32 tables.
inline constexpr int kRglWarpBisections = 40;

// Defaults (the database's files have n_t = 8, R = 32 or 64, V = 128, N = 128): measured agreement, cosine
// relative L2 at 20,000 uniform pairs, of GGX alpha 0.3 / alpha 0.1 / Lambert 0.8 + GGX 0.2 (f0 0.04):
//   n_t = 8,  R = 32, V = 128: 0.046 / - / -        (the slices' spacing near grazing dominates: Fresnel)
//   n_t = 16, R = 64, V = 128: 0.018 / 0.050 / 0.021
//   n_t = 24, R = 64, V = 64:  0.014 / 0.017 / 0.020 (the defaults: 2.0 MB; V = 64 loses nothing to 128)
//   n_t = 32, R = 64, V = 64:  0.013 / 0.013 / 0.020 (2.6 MB)
struct RglExportOptions {
  int theta_nodes = 24;        // n_t >= 2
  int value_resolution = 64;   // R >= 2
  int vndf_resolution = 64;    // V >= 2
  int ndf_resolution = 128;    // N >= 2
  std::string description;     // text written to the description field
};

struct RglExportSummary {
  int theta_nodes = 0, value_resolution = 0, vndf_resolution = 0, ndf_resolution = 0;
  long long nodes_below_horizon = 0;  // value nodes whose w_o is below the horizon (stored 0)
  long long bytes = 0;                // file size
};

RglExportSummary write_rgl_export(const std::string& path, const BrdfModel& model, const RglExportOptions& options);

}  // namespace icobrdf
