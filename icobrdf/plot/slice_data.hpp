#pragma once
// The remitted distribution of a spectrum for one incident direction (the paper's Figs. 4-6).
//
// For a coefficient matrix C of order N (icobrdf/core/spectrum/spectrum.hpp) the slice at incident direction w_i is
//   s(w_r) = K(w_i)^T C K(w_r) = K(w_r)^T u,   u = C^T K(w_i),
// in 1/sr: f for spectra of f, g = f cos(theta_i) for spectra of g (delta models). Truncation to an order
// N' <= N keeps the leading M(N') x M(N') block of C (the K functions of order <= N' come first in ANSI
// order), which is the orthogonal projection onto the modes of order <= N'.
#include <Eigen/Core>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"

namespace icobrdf::plot {

// Mean of the channels' coefficient matrices: the spectrum of the grey BRDF (R + G + B) / 3.
Eigen::MatrixXd channel_mean(const Spectrum& s);

// Leading block of `c` for `order` (<= the order of c, ArgumentError otherwise), then the low-pass filter
// with the weights of that order.
Eigen::MatrixXd truncated_coefficients(const Eigen::MatrixXd& c, int order, const LowPassFilter& filter);

// s(w_r) at each row of wr for the order-`order` matrix c.
Eigen::VectorXd slice_values(const Eigen::MatrixXd& c, int order, const Eigen::Vector3d& wi, const RowMatrix3d& wr);

// Remitted directions in the plane of incidence, by signed polar angle t in [-pi/2, pi/2] (radians):
// t > 0 on the forward side (azimuth phi_i + pi, where the mirror direction lies), t < 0 on the backward
// side (azimuth phi_i, the retro direction at t = -theta_i).
RowMatrix3d plane_of_incidence_directions(double phi_i, const Eigen::VectorXd& signed_theta);

}  // namespace icobrdf::plot
