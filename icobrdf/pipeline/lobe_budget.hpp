#pragma once
// Isotropic half-angle lobes within a byte budget: the grids a search over measured data visits and the
// bytes a lobe of a given shape stores, before it is fitted. Shared by the bank's search
// (icobrdf/pipeline/half_angle_representation.cpp) and `bench measured`'s small lobes
// (icobrdf/lab/measured_benchmark.cpp), so that both visit the same (n_t, d grid) pairs and count bytes alike.
//
// A lobe's bytes: HalfAngleFactors::bytes (factor values at their precision, integer column scales, channel
// scales of shared factors) + kLobeHeaderBytes. For each d grid (n_theta_d x n_phi_d) and rank, the search
// takes the largest n_t of kLobeBudgetNt whose lobe fits the budget: on the RGL files the error falls with n_t
// at fixed d grid and rank up to 128-256 (the specular peak's width in t), and the d grid and the rank are
// the choices that trade against it (measured with `bench measured`: 128x16x8 rank 4 for
// ilm_l3_37_matte at 2,700 B; 256 x 128x32 rank 4 at 37 KB for four of five materials).
#include <iterator>

#include "icobrdf/core/models/half_angle_factors.hpp"

namespace icobrdf {

// Bytes of a lobe beyond its factors: the 8 numbers describing its grids (n_t, n_phi_h, n_theta_d, n_phi_d,
// rank as int32; h_warp, cosine floor as float64; the quantity as one byte).
inline constexpr long long kLobeHeaderBytes = 5 * 4 + 2 * 8 + 1;

// Quantity of isotropic lobes of measured data under the cosine metric: q = f cos(theta_i) cos(theta_r), the
// metric's own integrand, which vanishes at the horizon, so that interpolating it between nodes costs least
// where the metric weighs least (grazing pairs). On RGL acrylic_felt_green, fitted to the reciprocal part with
// the metric's weights on 256 x 32x16 nodes, rank 6 per channel: held-out error 0.013 with this quantity; the
// bank's mean-cosine lobes (p = f (cos_i + cos_r) / 2, which stays finite at the horizon) reached 0.023 at
// every grid within its work cap, 85 % of their squared error at pairs with theta_i or theta_r > 75 deg.
inline constexpr HalfAngleQuantity kMeasuredLobeQuantity = HalfAngleQuantity::Cosine;

// d grids (n_theta_d, n_phi_d) in increasing size, from the coarsest a measured lobe holds to the glossy
// ladder's coarse end; and the n_t values taken per budget.
inline constexpr int kLobeBudgetD[][2] = {{8, 4}, {16, 4}, {16, 8}, {32, 8}, {32, 16}, {64, 16}, {64, 32}, {96, 32}, {128, 32}};
inline constexpr int kLobeBudgetNt[] = {8, 12, 16, 24, 32, 48, 64, 96, 128, 192, 256};

// Bytes of an isotropic lobe of this shape as stored: per-channel or shared factors (`channels` > 1 only) at
// precision p, + kLobeHeaderBytes.
inline long long stored_lobe_bytes(int channels, int rank, int n_t, int n_theta_d, int n_phi_d, bool shared, FactorPrecision p) {
  HalfAngleFactors shape;
  shape.n_t = n_t, shape.n_theta_d = n_theta_d, shape.n_phi_d = n_phi_d, shape.rank = rank, shape.precision = p;
  const int sets = shared ? 1 : channels;
  shape.u.assign(static_cast<size_t>(sets), RowMatrixXd(n_t, rank));
  shape.v.assign(static_cast<size_t>(sets), RowMatrixXd(static_cast<Eigen::Index>(n_theta_d) * n_phi_d, rank));
  if (shared) shape.channel_scales.resize(channels, rank);
  return static_cast<long long>(shape.bytes()) + kLobeHeaderBytes;
}

// The largest n_t of kLobeBudgetNt whose lobe (this rank, d grid and storage) takes at most `max_bytes`
// (< 0: no limit, the largest n_t); 0 when even the smallest does not fit.
inline int largest_n_t(long long max_bytes, int channels, int rank, int n_theta_d, int n_phi_d, bool shared, FactorPrecision p) {
  if (max_bytes < 0) return *std::prev(std::end(kLobeBudgetNt));
  int n_t = 0;
  for (const int nt : kLobeBudgetNt)
    if (stored_lobe_bytes(channels, rank, nt, n_theta_d, n_phi_d, shared, p) <= max_bytes) n_t = nt;
  return n_t;
}

}  // namespace icobrdf
