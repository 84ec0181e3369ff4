#pragma once
// A stored half-angle lobe: a BRDF as a sum of separable terms in half-angle coordinates (icobrdf/core/basis/half_angle.hpp):
//   q(h, d) = sum_{r < R} u_r(h) v_r(d)   per channel,
// where q = f (quantity F) or q = f cos(theta_i) cos(theta_r) (quantity Cosine). The cosine quantity is
// the integrand of the cosine error metric, cancels the microfacet 1/(4 cos cos) denominator, and makes
// Lambert exactly rank 2 (icobrdf/core/basis/half_angle.hpp). Evaluating the cosine quantity returns
// f = q / (max(cos_i, c) max(cos_r, c)) with c = cosine_floor(); near grazing f therefore carries the interpolation
// error of q amplified by 1/(cos_i cos_r).
//
// Grids (tensor products of node values; linear interpolation in each coordinate):
//  h: t in [0, 1] with theta_h = (pi/2) t^h_warp (default h_warp = 2: nodes crowd where lobes are, at
//     h = n), nodes t_k = k / (n_t - 1). Isotropic: u depends on t only (n_phi_h = 1). Anisotropic: also
//     on phi_h, nodes phi_h_j = 2 pi j / n_phi_h, periodic.
//     Anisotropic grids may be stretched (h_axis, h_scale_1, h_scale_2; identity 0, 1, 1): (theta_h, phi_h)
//     above are then the angles of the stretched half vector h', whose slopes are those of h rotated by
//     -h_axis (into the lobe's principal axes) and divided by (h_scale_1, h_scale_2):
//       s = (h_x, h_y) / h_z,  s_1 = cos(a) s_x + sin(a) s_y,  s_2 = -sin(a) s_x + cos(a) s_y,
//       h' ~ (s_1 / h_scale_1, s_2 / h_scale_2, 1),  a = h_axis.
//     An elliptical lobe (GGX or Beckmann with alpha_x != alpha_y: a function of the stretched slope) becomes
//     circular, so the t^2 warp resolves both of its widths with few phi_h nodes (icobrdf/core/fit/lobe_axes.hpp finds
//     the axes). The d coordinates always use the true h.
//  d: theta_d_a = (pi/2) a / (n_theta_d - 1); phi_d_b = pi b / n_phi_d, periodic with period pi.
//     Anisotropic representations measure phi_d from the world's x axis (phi_d + phi_h: the frame of the
//     minimal rotation taking h to +z, in which masking depends on d alone near h = n; Rusinkiewicz's frame
//     turns with phi_h and made rank-1 fits of anisotropic GGX 1.3x worse, measured).
//     Exchanging w_i and w_r adds pi to phi_d, so every stored representation is reciprocal by
//     construction; evaluation is bitwise reciprocal (icobrdf/core/basis/half_angle.hpp: the swap negates d_x, d_y
//     exactly, and phi_d is taken from the canonical one of (d_x, d_y) and (-d_x, -d_y)).
// Node order (rows of u and v; columns are the R terms):
//  u: row k * n_phi_h + j for (t_k, phi_h_j);  v: row a * n_phi_d + b for (theta_d_a, phi_d_b).
//
// Storage (what bytes() counts and the file holds; the in-memory values are always those the file stores):
//  Factor sets: per channel (u, v hold one matrix per channel), or shared: u, v hold one matrix each and
//     channel_scales (channels x rank) weighs term r of channel c, q_c = sum_r s[c, r] u_r(h) v_r(d) -- one
//     lobe shape for all channels with per-channel, per-term scales (a CP decomposition of the node values
//     over (h, d, channel)). Exact for a lobe whose channels are multiples of one shape per term (a grey
//     specular over a coloured body: rank 2 + rank 1 shared terms).
//  Precision of the factor values: float64, float32 (relative rounding 6e-8), or scaled integers int16 /
//     int8, one float64 scale per factor column: value = scale * k, |k| <= L = 2^(B-1) - 1, scale = max|column| / L
//     rounded to a float, so every value is within scale / 2 = max|column| / (2 L) (1 + 6e-8) of the fitted
//     one (1.5e-5 and 3.9e-3 of the column's largest value). quantize() rounds the factors to it in memory.
//
// The fit of such a lobe to a BRDF is icobrdf/core/fit/half_angle_fit.hpp.
#include <Eigen/Core>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/basis/horizon.hpp"

namespace icobrdf {

using RowMatrixXd = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

enum class HalfAngleQuantity { F, Cosine, MeanCosine };  // names "f", "cosine", "mean-cosine"
// What interpolation does with the corners of a cell that are node pairs below the horizon:
//  All:   they take part like any other (format 2.0 lobes, fitted with extended values there);
//  Valid: they are dropped and the weights of the others renormalized, so values at such nodes are never
//         used and the fit needs none (lobes written since format 3.0). Interpolation in a cell straddling
//         the horizon is then first-order instead of second; q is small there (cosine quantity).
enum class HorizonCorners { All, Valid };  // names "all", "valid"
const char* horizon_corners_name(HorizonCorners c);
HorizonCorners horizon_corners_from_name(const std::string& name);  // ArgumentError for an unknown name
const char* half_angle_quantity_name(HalfAngleQuantity q);
// ArgumentError for an unknown name.
HalfAngleQuantity half_angle_quantity_from_name(const std::string& name);

enum class FactorPrecision { Float64, Float32, Int16, Int8 };  // names "float64", "float32", "int16", "int8"
const char* factor_precision_name(FactorPrecision p);
FactorPrecision factor_precision_from_name(const std::string& name);  // ArgumentError for an unknown name
// Bytes of one stored factor value.
int factor_precision_bytes(FactorPrecision p);
// Largest |k| of an integer precision (32767, 127); 0 for the floating ones.
int factor_precision_levels(FactorPrecision p);


// Largest rank of a lobe with shared factors (its evaluation keeps the terms of one pair on the stack).
inline constexpr int kMaxStoredRank = 64;

// Bounds of the h-grid scales (h_scale_1 / h_scale_2 ratios of up to 1e4: far beyond any measured lobe).
inline constexpr double kMinHScale = 1e-2, kMaxHScale = 1e2;

struct HalfAngleFactors {
  HalfAngleQuantity quantity = HalfAngleQuantity::Cosine;
  bool isotropic = true;
  double h_warp = 2.0;  // theta_h = (pi/2) t^h_warp
  HorizonCorners corners = HorizonCorners::Valid;
  // Node placement of t, theta_d and phi_d (phi_h nodes always start at 0). Ends (default): t_k = k/(n_t-1),
  // theta_d_a = (pi/2) a/(n_theta_d-1), phi_d_b = pi b/n_phi_d. Centred: the centres of equal bins,
  // t_k = (k+1/2)/n_t, theta_d_a = (pi/2)(a+1/2)/n_theta_d, phi_d_b = pi (b+1/2)/n_phi_d -- the nodes of the
  // MERL table (icobrdf/io/merl.hpp), so that a lobe can be fitted to its values as they are. Interpolation is
  // linear between nodes and constant beyond the first and last centres.
  bool centred = false;
  double node_t(int k) const;
  double node_theta_d(int a) const;
  double node_phi_d(int b) const;
  // Dual cells (the weights' integration ranges): [lo, hi] in t and in theta_d.
  void t_cell(int k, double& lo, double& hi) const;
  void theta_d_cell(int a, double& lo, double& hi) const;
  // Stretch of the h grid (anisotropic only; see the header comment): axis angle [rad] and the two scales.
  double h_axis = 0.0, h_scale_1 = 1.0, h_scale_2 = 1.0;
  int n_t = 0, n_phi_h = 1, n_theta_d = 0, n_phi_d = 0, rank = 0;
  std::vector<RowMatrixXd> u;  // per factor set: (n_t * n_phi_h) x rank
  std::vector<RowMatrixXd> v;  // per factor set: (n_theta_d * n_phi_d) x rank
  // Shared factor sets (see Storage above): channels x rank; empty when every channel has its own u and v.
  RowMatrixXd channel_scales;
  FactorPrecision precision = FactorPrecision::Float64;

  bool shared() const { return channel_scales.size() > 0; }
  int channels() const { return shared() ? static_cast<int>(channel_scales.rows()) : static_cast<int>(u.size()); }
  int h_nodes() const { return n_t * n_phi_h; }
  int d_nodes() const { return n_theta_d * n_phi_d; }
  // Stored bytes: factor values x factor_precision_bytes(precision), + 8 per factor column for the integer
  // scales, + 8 per channel scale (float64).
  std::size_t bytes() const;
  // Rounds u and v to `precision` (float32: round to nearest float; integers: per column, see Storage);
  // idempotent. The evaluation then gives what a file's reader gets.
  void quantize();
  // The integer scale of a factor column (max|column| / levels rounded to a float; 0 for an all-zero column).
  static double column_scale(const Eigen::Ref<const Eigen::VectorXd>& column, FactorPrecision p);
  double theta_h_of_t(double t) const;
  bool stretched() const { return h_axis != 0.0 || h_scale_1 != 1.0 || h_scale_2 != 1.0; }
  // The true half vector, not normalized, at grid angles (theta_h, phi_h) (those of h'):
  // Rz(h_axis) (h_scale_1 sin(theta_h) cos(phi_h), h_scale_2 sin(theta_h) sin(phi_h), cos(theta_h)).
  Eigen::Vector3d h_of_grid_angles(double theta_h, double phi_h) const;
  // Floor of cos(theta_i) and of cos(theta_r) when the cosine quantity is divided back to f:
  // sin(one theta_d step) = sin((pi/2) / (n_theta_d - 1)) (ends) or sin((pi/2) / n_theta_d) (centred), the
  // cosine one theta_d step from the horizon. Closer to the horizon the
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
  // otherwise, h_warp in [0.25, 8], no stretch when isotropic, h_axis in [-pi, pi] and scales in
  // [kMinHScale, kMaxHScale], rank >= 0, >= 1 channel, u and v of the stated sizes, all finite; shared: one
  // factor set and channel_scales of rank columns, finite.
  // InputError naming the first violation.
  void validate() const;
};

// Node weights a_h (h_nodes) and b_d (d_nodes) of the options' grids (exact dual-cell integrals of dw_h
// and 4 cos(theta_d) dw_d): sum a = 2 pi (upper hemisphere of h), sum b = 4 pi. On a stretched grid a_h is
// the integral of dw_h = J dw_h' over the cell of h' (J = s1 s2 / |h_of_grid_angles|^3, the Jacobian of the
// stretch of slopes times cos^3 theta_h / cos^3 theta_h'), by 8 x 8 Gauss-Legendre points per cell.
Eigen::VectorXd half_angle_h_weights(const HalfAngleFactors& grid);
Eigen::VectorXd half_angle_d_weights(const HalfAngleFactors& grid);
// Per node: sin and cos of theta and of phi (h nodes: the true h, phi_h = 0 for isotropic grids; d nodes:
// phi_d as stored). A node pair is on or above the horizon iff
//   cos_h cos_d - sin_h sin_d |cos(phi_d - phi_h)| >= -kHorizonSlack
// (w_i,z and w_r,z are cos_h cos_d -/+ sin_h sin_d cos(phi_d - phi_h)); the fit and the evaluation decide it
// by this one expression.
struct HalfAngleNodeTrig {
  // Row i: sin(theta), cos(theta), cos(phi), sin(phi) of node i (one row per node: one cache line per lookup).
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> m;
  double s(int i) const { return m(i, 0); }
  double c(int i) const { return m(i, 1); }
  double cp(int i) const { return m(i, 2); }
  double sp(int i) const { return m(i, 3); }
};
HalfAngleNodeTrig half_angle_h_trig(const HalfAngleFactors& grid);
HalfAngleNodeTrig half_angle_d_trig(const HalfAngleFactors& grid);
inline bool node_pair_valid(const HalfAngleNodeTrig& h, int i, const HalfAngleNodeTrig& d, int j) {
  const double* a = h.m.data() + 4 * i;
  const double* b = d.m.data() + 4 * j;
  return a[1] * b[1] - a[0] * b[0] * std::abs(a[2] * b[2] + a[3] * b[3]) >= -kHorizonSlack;
}

// f of a lobe at one direction pair, for per-sample callers (a renderer's eval at each path vertex): bitwise
// the values of HalfAngleFactors::eval at the same pair (both run the same per-pair code); what that code needs
// besides the factors (the stretch, the cosine floor, the node trig tables of HorizonCorners::Valid) is
// computed once here instead of once per batch, and nothing is allocated per call. The per-pair function of the
// lobe's kind (isotropy, rank 1-4 unrolled) is chosen here once; for isotropic lobes with HorizonCorners::Valid,
// the cells the horizon cuts are found from a per-d-node count of valid h nodes (4 bytes per d node, built by
// testing every node pair once), not from the node trig at every pair (the same cells: the test
// HalfAnglePairEvaluator.BitwiseTheBatchForEveryKindOfLobeAndHardPairs).
// wi, wr: 3 doubles each (unit vectors); out: channels() doubles [1/sr]; 0 where a direction is below the
// horizon (z < -kHorizonSlack). eval may be called from several threads at once.
struct HalfAnglePairContext;
class HalfAnglePairEvaluator {
 public:
  // ArgumentError for a null lobe.
  explicit HalfAnglePairEvaluator(std::shared_ptr<const HalfAngleFactors> lobe);
  int channels() const { return lobe_->channels(); }
  const HalfAngleFactors& lobe() const { return *lobe_; }
  void eval(const double* wi, const double* wr, double* out) const;

 private:
  std::shared_ptr<const HalfAngleFactors> lobe_;
  std::shared_ptr<const HalfAnglePairContext> context_;
};

// The pair of node (h row, d row) of a grid (isotropic grids: phi_h = 0).
void half_angle_node_pair(const HalfAngleFactors& grid, int h_row, int d_row, Eigen::Vector3d& wi,
                          Eigen::Vector3d& wr);

}  // namespace icobrdf
