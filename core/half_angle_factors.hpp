#pragma once
// A BRDF as a sum of separable terms in half-angle coordinates (core/half_angle.hpp):
//   q(h, d) = sum_{r < R} u_r(h) v_r(d)   per channel,
// where q = f (quantity F) or q = f cos(theta_i) cos(theta_r) (quantity Cosine). The cosine quantity is
// the integrand of the cosine error metric, cancels the microfacet 1/(4 cos cos) denominator, and makes
// Lambert exactly rank 2 (core/half_angle.hpp). Evaluating the cosine quantity returns
// f = q / (max(cos_i, c) max(cos_r, c)) with c = cosine_floor(); near grazing f therefore carries the interpolation
// error of q amplified by 1/(cos_i cos_r).
//
// Grids (tensor products of node values; linear interpolation in each coordinate):
//  h: t in [0, 1] with theta_h = (pi/2) t^h_warp (default h_warp = 2: nodes crowd where lobes are, at
//     h = n), nodes t_k = k / (n_t - 1). Isotropic: u depends on t only (n_phi_h = 1). Anisotropic: also
//     on phi_h, nodes phi_h_j = 2 pi j / n_phi_h, periodic.
//  d: theta_d_a = (pi/2) a / (n_theta_d - 1); phi_d_b = pi b / n_phi_d, periodic with period pi.
//     Anisotropic representations measure phi_d from the world's x axis (phi_d + phi_h: the frame of the
//     minimal rotation taking h to +z, in which masking depends on d alone near h = n; Rusinkiewicz's frame
//     turns with phi_h and made rank-1 fits of anisotropic GGX 1.3x worse, measured).
//     Exchanging w_i and w_r adds pi to phi_d, so every stored representation is reciprocal by
//     construction; evaluation is bitwise reciprocal (core/half_angle.hpp: the swap negates d_x, d_y
//     exactly, and phi_d is taken from the canonical one of (d_x, d_y) and (-d_x, -d_y)).
// Node order (rows of u and v; columns are the R terms):
//  u: row k * n_phi_h + j for (t_k, phi_h_j);  v: row a * n_phi_d + b for (theta_d_a, phi_d_b).
//
// Fitting (fit_half_angle): q is sampled at every (h node, d node) whose (w_i, w_r) are both on or above
// the horizon (within kHorizonSlack; the others are missing). For isotropic fits only phi_h = 0 is
// sampled. Node weights a_h, b_d are the exact integrals of the measures dw_h and 4 cos(theta_d) dw_d over
// the nodes' dual cells (midpoints between nodes; phi_d counts twice, once for each of its two copies in
// [0, 2 pi)), so that
//   e^2 = sum_valid a_h b_d (Q - U V^T)^2 / sum_valid a_h b_d Q^2
// approximates the squared relative L2 error of q over pairs uniform in (w_i, w_r)
// (dw_i dw_r = 4 cos(theta_d) dw_h dw_d). The mask is not separable, so the weighted low-rank problem is
// solved by alternating weighted least squares (one R x R system per node, with a ridge of 1e-14 of its
// trace so that nodes seen by few valid pairs stay determined), started for each new rank from the previous
// solution plus the leading singular pair of the zero-filled weighted residual. The rank grows from 1
// until e <= target for every channel. Channels are fitted independently and share the rank; a channel
// that meets the target at a lower rank keeps zero terms above it.
// Missing nodes that share an interpolation cell with a valid node are not left free: their values would
// be arbitrary extrapolations of the factors (first-order error in every cell straddling the horizon). They
// get the natural extension of q across the horizon, f at the directions pushed onto the horizon times
// the signed cosines (C^1 across the boundary for the cosine quantity), with a small weight
// (options.extension_weight); the reported error counts the valid nodes only.
#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/grid.hpp"

namespace icobrdf {

using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

enum class HalfAngleQuantity { F, Cosine };  // names "f", "cosine"
const char* half_angle_quantity_name(HalfAngleQuantity q);
// ArgumentError for an unknown name.
HalfAngleQuantity half_angle_quantity_from_name(const std::string& name);


// Largest rank fit_half_angle accepts (its per-node R x R solves use fixed-capacity matrices).
inline constexpr int kMaxFitRank = 32;

struct HalfAngleFactors {
  HalfAngleQuantity quantity = HalfAngleQuantity::Cosine;
  bool isotropic = true;
  double h_warp = 2.0;  // theta_h = (pi/2) t^h_warp
  int n_t = 0, n_phi_h = 1, n_theta_d = 0, n_phi_d = 0, rank = 0;
  std::vector<RowMatrixXd> u;  // per channel: (n_t * n_phi_h) x rank
  std::vector<RowMatrixXd> v;  // per channel: (n_theta_d * n_phi_d) x rank

  int channels() const { return static_cast<int>(u.size()); }
  int h_nodes() const { return n_t * n_phi_h; }
  int d_nodes() const { return n_theta_d * n_phi_d; }
  // Stored doubles x 8.
  std::size_t bytes() const;
  double theta_h_of_t(double t) const;
  // Floor of cos(theta_i) and of cos(theta_r) when the cosine quantity is divided back to f:
  // sin((pi/2) / (n_theta_d - 1)), the cosine one theta_d step from the horizon. Closer to the horizon the
  // grid does not resolve q, whose interpolation error divided by the cosines would grow without bound
  // (1e9 1/sr at the rim with a floor of 1e-12 on the product); f there is q / floor^2 at most.
  double cosine_floor() const;
  double t_of_theta_h(double theta_h) const;
  // f at pairs (rows x channels); 0 where a direction is below the horizon (z < -kHorizonSlack).
  // Threads over rows (OpenMP). ArgumentError on mismatched shapes.
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const;
  Eigen::MatrixXd eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const;
  // q (the stored quantity) instead of f.
  void eval_quantity(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const;
  // Checks loaded data: n_t >= 2, n_theta_d >= 2, n_phi_d >= 1, n_phi_h = 1 when isotropic and >= 1
  // otherwise, h_warp in [0.25, 8], rank >= 0, >= 1 channel, u and v of the stated sizes, all finite.
  // InputError naming the first violation.
  void validate() const;
};

// f at batches of pairs: out is rows x channels.
using PairSampler =
    std::function<void(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out)>;

class BrdfModel;
// The regular part of a model as a sampler (the model must outlive it).
PairSampler model_pair_sampler(const BrdfModel& model);
// n pairs with both directions uniform in solid angle (core/direction.hpp uniform_direction, w_i drawn
// before w_r), the held-out pairs of the representation's error figures.
void uniform_pairs(int n, std::uint64_t seed, RowMatrix3d& wi, RowMatrix3d& wr);

struct HalfAngleFitOptions {
  HalfAngleQuantity quantity = HalfAngleQuantity::Cosine;
  bool isotropic = true;
  double h_warp = 2.0;
  int n_t = 64;
  int n_phi_h = 32;  // ignored (1) when isotropic
  int n_theta_d = 64;  // grazing masking makes q steep in theta_d: 32 -> 64 cut GGX 0.1's error 6x
  int n_phi_d = 16;
  double target = 0.01;  // relative weighted node error of q per channel
  int max_rank = 8;
  int max_sweeps = 200;            // ALS sweeps per rank
  double sweep_tolerance = 1e-6;   // stop when the objective decreases by less than this fraction of itself
  int fixed_rank = 0;              // > 0: fit exactly this rank (no target check, no refusal)
  // Weight (relative to a valid node's) of the extended values at missing nodes next to valid ones;
  // 0 leaves them missing.
  double extension_weight = 0.05;
};

struct HalfAngleFitReport {
  int rank = 0;
  std::vector<double> error;                       // per channel, at the final rank
  std::vector<std::vector<double>> error_by_rank;  // [channel][r - 1]: e after fitting rank r
  // [channel][r]: weighted singular values of the fitted U V^T over all nodes, relative to the weighted
  // norm of Q (sum of squares over valid nodes = 1 - e^2 when the fit is orthogonal).
  std::vector<std::vector<double>> energies;
  std::vector<int> sweeps_by_rank;  // ALS sweeps used at each rank (maximum over channels)
  double valid_fraction = 0;        // share of node pairs on or above the horizon
  double seconds = 0;               // sampling + fitting
};

struct HalfAngleFit {
  HalfAngleFactors factors;
  HalfAngleFitReport report;
};

// Node weights a_h (h_nodes) and b_d (d_nodes) of the options' grids (exact dual-cell integrals of dw_h
// and 4 cos(theta_d) dw_d): sum a = 2 pi (upper hemisphere of h), sum b = 4 pi.
Eigen::VectorXd half_angle_h_weights(const HalfAngleFactors& grid);
Eigen::VectorXd half_angle_d_weights(const HalfAngleFactors& grid);
// The pair of node (h row, d row) of a grid (isotropic grids: phi_h = 0).
void half_angle_node_pair(const HalfAngleFactors& grid, int h_row, int d_row, Eigen::Vector3d& wi,
                          Eigen::Vector3d& wr);

// Fits q of a BRDF given by `sampler` (`channels` columns). ArgumentError for invalid options;
// UnsupportedError when max_rank cannot meet the target (message with the best error reached).
HalfAngleFit fit_half_angle(const PairSampler& sampler, int channels, const HalfAngleFitOptions& options);

}  // namespace icobrdf
