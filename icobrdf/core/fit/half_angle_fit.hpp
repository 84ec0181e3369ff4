#pragma once
// The fit of a half-angle lobe (icobrdf/core/models/half_angle_factors.hpp: grids, node order, evaluation) to
// a BRDF given at pairs of directions.
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

#include <cstdint>
#include <functional>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/models/half_angle_factors.hpp"

namespace icobrdf {

// Largest rank fit_half_angle accepts (its per-node R x R solves use fixed-capacity matrices).
inline constexpr int kMaxFitRank = 32;

// f at batches of pairs: out is rows x channels.
using PairSampler =
    std::function<void(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out)>;

class BrdfModel;
// The regular part of a model as a sampler (the model must outlive it).
PairSampler model_pair_sampler(const BrdfModel& model);
// n pairs with both directions uniform in solid angle (icobrdf/core/basis/direction.hpp uniform_direction, w_i drawn
// before w_r), the held-out pairs of the representation's error figures.
void uniform_pairs(int n, std::uint64_t seed, RowMatrix3d& wi, RowMatrix3d& wr);

struct HalfAngleFit;

struct HalfAngleFitOptions {
  HalfAngleQuantity quantity = HalfAngleQuantity::Cosine;
  HorizonCorners corners = HorizonCorners::Valid;
  bool isotropic = true;
  double h_warp = 2.0;
  double h_axis = 0.0, h_scale_1 = 1.0, h_scale_2 = 1.0;  // stretch of the h grid (anisotropic only)
  bool centred = false;                                     // node placement (HalfAngleFactors::centred)
  // Non-finite sampled values (missing data, e.g. a MERL table's -1 entries) are left out of the fit like
  // nodes below the horizon (counted in the report); false: they are an ArgumentError.
  bool skip_missing = false;
  int n_t = 64;
  int n_phi_h = 32;  // ignored (1) when isotropic
  int n_theta_d = 64;  // grazing masking makes q steep in theta_d: 32 -> 64 cut GGX 0.1's error 6x
  int n_phi_d = 16;
  double target = 0.01;  // relative weighted node error of q per channel
  int max_rank = 8;
  int max_sweeps = 200;            // ALS sweeps per rank
  double sweep_tolerance = 1e-6;   // stop when the objective decreases by less than this fraction of itself
  int fixed_rank = 0;              // > 0: fit exactly this rank (no target check, no refusal)
  // Channels share one set of factors with per-channel, per-term scales (HalfAngleFactors::channel_scales),
  // fitted by alternating least squares over u, the scales and v; the rank grows until every channel meets
  // the target. False: each channel its own factors.
  bool shared_channels = false;
  // Precision the factors are stored in: the fitted factors are rounded to it (HalfAngleFactors::quantize)
  // before they are returned, so that what is evaluated is what a file holds.
  FactorPrecision precision = FactorPrecision::Float64;
  // Weight (relative to a valid node's) of the extended values at missing nodes next to valid ones;
  // 0 leaves them missing. Only HorizonCorners::All uses such values (0.05 there; measured best on the
  // glossy lobes); with Valid they would only pull the factors away from the valid nodes.
  double extension_weight = 0.0;
  // Called after every rank r (1, 2, ..., the rank returned) with the fit as fixed_rank = r would return it
  // (factors stored at `precision`, report up to r); false stops the growth there, and that fit is returned
  // (with fixed_rank = 0 it is then checked against the target as usual). The ranks grow one term at a time
  // from the previous rank's factors, so one fit judges ranks 1..R for the ALS work of rank R alone, where
  // fitting each rank on its own costs about (R + 1) / 2 times as much.
  std::function<bool(const HalfAngleFit&)> on_rank;
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
  long long missing_nodes = 0;      // node pairs above the horizon left out as missing (skip_missing)
  double seconds = 0;               // sampling + fitting
};

struct HalfAngleFit {
  HalfAngleFactors factors;
  HalfAngleFitReport report;
};

// Fits q of a BRDF given by `sampler` (`channels` columns). ArgumentError for invalid options;
// UnsupportedError when max_rank cannot meet the target (message with the best error reached).
HalfAngleFit fit_half_angle(const PairSampler& sampler, int channels, const HalfAngleFitOptions& options);

}  // namespace icobrdf
