#pragma once
// HalfVectorTable: importance sampling of reflected directions by tables over the half vector, built once for
// a set of incident directions (nodes) and blended between them, so that nothing is built per incident
// direction when sampling.
//
// Cells: the hemisphere of the half vector h in the coordinates of a half-angle lobe
// (icobrdf/core/models/half_angle_factors.hpp): t in [0, 1] with theta_h = (pi/2) t^t_warp, n_t equal bins of t
// (so that cells crowd at h = n, where glossy lobes are), and n_phi equal bins of phi_h in [-pi, pi) (isotropic
// tables with an even n_phi store the bins in [0, pi) and draw their mirror image half the time: q is even in
// phi_h there, see HalfVectorTableOptions::mirror). Cell
// (k, j) has the solid angle A_kj = (cos theta_k - cos theta_k+1) (2 pi / n_phi).
// Nodes: incident directions at theta_a = theta_max a / (n_theta - 1), a < n_theta (theta_max = 89 degrees: a
// spectrum of g = f cos is infinite at grazing), and, for an anisotropic BRDF, phi_b = 2 pi b / n_azimuth. With
// n_azimuth = 1 (isotropic BRDFs) the node's w_i has phi = 0 and w_i is first turned by -phi_i about the
// normal (w_r and h turn with it; solid angles are kept).
// Per node, the mass of cell (k, j) is m = integral over the cell of q(h) dw_h, with
//   q(h) = fbar(w_i, w_r(h)) cos(theta_r) 4 (w_i . h),  w_r(h) = 2 (w_i . h) h - w_i,
// fbar >= 0 the caller's value (a material's mean over channels of max(f, 0)), 0 where w_r is below the horizon
// or w_i . h <= 0; 4 (w_i . h) is the Jacobian dw_r / dw_h, so the masses sum to the directional albedo of fbar
// (the estimate albedo() returns). m is estimated by the midpoint rule of 2 x 2 sub-cells equal in solid angle;
// in a cell the horizon of w_r cuts, by the midpoint rule of 8 x 8 points (q = 0 beyond the horizon): at normal
// incidence the horizon lies at theta_h = 45 degrees, and a cell whose four sub-cell centres all reflect below
// it can still hold a sliver of w_r up to 1 degree above it (3e-4 of a Lambertian albedo with 64 t bins),
// which the floor alone would draw so rarely that the estimator's typical value misses it.
// A cell with a sub-cell centre or a corner whose w_r is above the horizon gets at least
// kHalfVectorFloor x (mean mass of such cells): a cell whose four points miss a narrow feature of f is still
// drawn, so the density is positive wherever f cos can be (the estimator stays unbiased), at a cost of at most
// that fraction of the draws.
// Density: within a cell the density in solid angle is linear in each of the cell's coordinates xi (from its
// upper to its lower cos theta_h edge) and eta (from its lower to its upper phi_h edge), per node:
//   g(xi, eta) = (1 + a (xi - 1/2)) (1 + b (eta - 1/2)),  mean 1 over the cell, |a|, |b| <= kHalfVectorMaxSlope,
// with the slopes a, b fitted to the 2 x 2 sub-cell values of q (in a cell the horizon cuts, to the first
// moments of q over its 8 x 8 points: the density's mean xi is 1/2 + a / 12), so that the draws follow f cos
// within the cell to first order (where the horizon cuts a cell the density falls towards it instead of
// staying flat). The blend of the nodes (linear in theta_i, taken as blend_theta(cos theta_i), and
// periodic-linear in phi_i when anisotropic) picks one node per draw with its blend weight (by u2), so the density
// of w_r is
//   pdf(w_r) = sum_n weight_n P_n(cell of h) g_n(xi, eta) / A_cell / (4 w_i . h)   [1/sr].
// Draws per call cost O(1): the cell from an alias table per node (Walker/Vose: one entry of 12 bytes, its
// threshold in float, so a cell is drawn with its mass to about 1e-7 relative, the float rounding of the
// masses that pdf() reads; beside it the alias cell's slopes, so that a draw reads the entry and its own cell
// at once instead of one after the other), the position within it from what is left of u1; the density of
// the drawn node at the drawn position uses the slopes the draw used. The cell index depends on u1 alone,
// not on the node: the alias entries and the masses and slopes are stored cell-major (the nodes of one cell
// side by side), so the entries a draw reads are fetched before the blend has picked the node
// (prefetch_draw: RenderMaterial::sample 223-229 -> 204-208 ns with the defaults, old and new in one program,
// three interleaved runs; before, u1 picked the node and then the cell, node-major), and the density at a
// drawn or given cell reads one or two cache lines; the cell of a half vector is found without atan2 for
// theta_h (a lookup on
// (1 - cos theta_h)^(1/4), then the exact cos edges decide) and with one atan2 for phi_h.
// Memory: 8 + 12 bytes per node and cell (48 nodes x 8192 mirrored cells, the defaults: 7.9 MB). Alias
// entries of 32 bytes that also carried the alias cell's masses and slopes of nodes n - 1, n, n + 1 (so an
// aliased draw's density would need no second access) doubled that to 15.7 MB; measured in one process they
// made sample() alone 2-5 ns faster but RenderMaterial::sample 4-8 ns slower (there the second access
// overlaps the evaluation of f), so the entries stay at 12 bytes.
// sample() fails (returns false) for a w_r below the horizon (a zero of the caller's estimator: f is 0 there).
// Accuracy: the weights f cos / pdf vary within a cell as f departs from the linear density over it, and
// between nodes as the BRDF does between neighbouring incident angles (the horizon of w_r moves under the
// h cells with theta_i): refine n_t, n_phi and n_theta for narrow lobes (the defaults resolve a GGX lobe of
// alpha 0.05 with about 12 bins of t across its width). Measured relative standard deviations of the weights,
// GGX alpha 0.3 at theta_i = 0 / 45 / 75 degrees: 0.010 / 0.013 / 0.029 with 48 nodes and the blend of
// blend_theta (0.010 / 0.011 / 0.037 with the blend's earlier atan2; 0.010 / 0.025 / 0.069 with 24 nodes;
// 0.035 / 0.044 / 0.079 with 24 and a constant density per cell); GGX alpha 0.05: 0.0016 / 0.0039 / 0.025
// (RenderMaterial.WeightsOfGgxLobesSpreadLittle prints them, 10,000 draws each).
// Thread safety: const methods may be called from several threads at once; no allocation in them.
#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

// The floor of a cell's mass, as a fraction of the mean mass of the cells that can hold reflected directions.
inline constexpr double kHalfVectorFloor = 1e-4;
// The largest polar angle of an incident node [rad] (89 degrees).
inline constexpr double kHalfVectorThetaMax = 89.0 * M_PI / 180.0;
// The largest |slope| of the density within a cell: the density stays >= 0.1 of the cell's mean everywhere in
// it. With slopes up to 2 it reached 0 at a cell's edge, and near the horizon (theta_i 45 and 75 deg) weights
// f cos / pdf grew without bound towards such an edge (measured 3e6 x the albedo at theta_r 89.99 deg).
inline constexpr double kHalfVectorMaxSlope = 1.8;
// Slopes within a cell are stored as integers in units of 1 / kHalfVectorSlopeUnit (|slope| <= 2).
inline constexpr double kHalfVectorSlopeUnit = 16000.0;
// Slots of the lookup from (1 - cos theta_h)^(1/4) to the t bin (a start for the exact search of the edges:
// at most a few bins per slot for t_warp in [1, 4] and 128 bins).
inline constexpr int kHalfVectorTLookup = 1024;

struct HalfVectorTableOptions {
  int theta_nodes = 48;   // incident polar angles (>= 2)
  int azimuth_nodes = 1;  // incident azimuths (1: isotropic; else >= 4)
  int t_bins = 128;       // bins of t (>= 4)
  int phi_bins = 128;     // bins of phi_h (>= 4)
  double t_warp = 2.0;    // theta_h = (pi/2) t^t_warp, in [1, 4]
  // Isotropic (azimuth_nodes = 1) with an even phi_bins: store only the bins of phi_h in [0, pi) (q is even in
  // phi_h for the nodes' w_i in the xz plane) and draw the image phi_h -> -phi_h with probability 1/2: half the
  // memory, so twice as many of a draw's random reads hit the caches; the same density.
  bool mirror = true;
};

// fbar at rows of pairs (w_i, w_r) (n x 3 each): n values >= 0 (a caller's max(f, 0), averaged over channels).
using NonNegativeBrdf = std::function<Eigen::VectorXd(const RowMatrix3d& wi, const RowMatrix3d& wr)>;

// The half vector h = normalize(w_i + w_r) of a reflected pair and c = w_i . h (the Jacobian dw_r / dw_h is
// 1 / (4 c)); false when w_i + w_r = 0 or c <= 0 (no density there).
inline bool reflection_half_vector(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr, Eigen::Vector3d& h, double& c) {
  h = wi + wr;
  const double len = h.norm();
  if (!(len > 0.0)) return false;
  h /= len;
  c = wi.dot(h);
  return c > 0.0;
}

// The nodes blended for an incident direction: up to 4 nodes with weights summing to 1, and (isotropic) the
// turn Rz(-phi_i) = [[c, s], [-s, c]] taking w_i into the nodes' frame.
struct HalfVectorBlend {
  int count = 0;
  int node[4] = {0, 0, 0, 0};
  double weight[4] = {0, 0, 0, 0};
  double c = 1, s = 0;
};

class HalfVectorTable {
 public:
  // The node layout alone (used for other per-node tables over the same incident directions).
  static HalfVectorBlend blend(const HalfVectorTableOptions& options, const Eigen::Vector3d& wi);
  // The polar angle the blend interpolates in, from cos(theta) = z alone (w_i is taken to be unit): 2 asin(u),
  // u = sin(theta / 2) = sqrt((1 - z) / 2), by the Taylor series of asin to u^15. Its truncation error grows
  // with theta: below 1.2e-4 rad (0.4 % of the nodes' spacing with the defaults) up to theta_max, 0 at the
  // normal. A square root and 7 multiply-adds instead of the square root, division and polynomial of an
  // atan2: the blend starts every draw's chain of dependent steps (sample() and pdf() blend alike, so their
  // densities agree however the weights are taken).
  static double blend_theta(double z);
  static Eigen::Vector3d node_direction(const HalfVectorTableOptions& options, int n);
  // ArgumentError for options out of range.
  static void check(const HalfVectorTableOptions& options);
  // The most cache lines prefetch_draw fetches (one cell's alias entries of every node: 9 lines for 48
  // nodes; an anisotropic table's 384 nodes would take 72, more than the core keeps in flight).
  static constexpr int kPrefetchLines = 12;
  // Whether the tables store only phi_h >= 0 (HalfVectorTableOptions::mirror taken up: isotropic, even phi_bins).
  static bool stores_mirror_image(const HalfVectorTableOptions& o) { return o.azimuth_nodes == 1 && o.phi_bins % 2 == 0 && o.mirror; }
  // The memory the tables take: nodes x stored cells x 20 bytes (a CellEntry of 8 and an alias entry of 12),
  // plus the construction's per-node work arrays (about 370 bytes per stored cell: the sub-cell half vectors,
  // their pairs and values). With the defaults: tables 7.9 MB, 10.8 MB with the work arrays; anisotropic
  // (RenderMaterialOptions' 24 x 16 nodes, 128 x 128 bins): 126 MB, 132 MB. The constructor refuses options
  // needing more than available_memory()
  // (icobrdf/core/support/memory_budget.hpp) with a ResourceError before it allocates.
  static double bytes(const HalfVectorTableOptions& options);

  HalfVectorTable() = default;
  // ArgumentError for options out of range; ResourceError when bytes(options) exceeds the memory available;
  // UnsupportedError when fbar returns a negative or non-finite value (the message names the pair).
  HalfVectorTable(const NonNegativeBrdf& fbar, const HalfVectorTableOptions& options);
  const HalfVectorTableOptions& options() const { return opt_; }
  bool empty() const { return cells_of_nodes_.empty(); }
  int nodes() const { return opt_.theta_nodes * opt_.azimuth_nodes; }
  // The incident direction of node n (n = a * azimuth_nodes + b).
  Eigen::Vector3d node_direction(int n) const { return node_direction(opt_, n); }
  // The estimate of the directional albedo of fbar at node n (the sum of its masses before the floor).
  double node_albedo(int n) const { return albedo_[static_cast<size_t>(n)]; }
  // The same blended to w_i as the densities are.
  double albedo(const Eigen::Vector3d& wi) const { return albedo(blend(opt_, wi)); }
  double albedo(const HalfVectorBlend& b) const;
  // A draw for w_i (unit, z >= 0) from u1, u2 in [0, 1): w_r and its density (pdf(w_i, w_r)); false when no
  // node of the blend has mass (an all-zero fbar) or w_r is below the horizon. u1 gives the cell and the
  // position in it along xi; u2 the node, then (mirrored) the image, then the position along eta.
  bool sample(const Eigen::Vector3d& wi, double u1, double u2, Eigen::Vector3d& wr, double& pdf) const {
    return sample(blend(opt_, wi), wi, u1, u2, wr, pdf);
  }
  double pdf(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const { return pdf(blend(opt_, wi), wi, wr); }
  // The same with the blend of w_i already known (blend(options(), wi)).
  bool sample(const HalfVectorBlend& b, const Eigen::Vector3d& wi, double u1, double u2, Eigen::Vector3d& wr, double& pdf) const;
  double pdf(const HalfVectorBlend& b, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const;
  // Starts fetching what sample(..., u1, ...) reads first, before the blend of w_i is known: the alias
  // entries of every node at u1's cell index (u1 alone gives it), when they span at most kPrefetchLines cache
  // lines (isotropic tables: 48 nodes, 9 lines); nothing otherwise. A hint only: no effect on any value.
  void prefetch_draw(double u1) const;

 private:
  struct AliasEntry {
    float keep;  // draw this cell when the fraction is below keep, else the alias
    int alias;
    std::int16_t a, b;  // the alias cell's slopes for this node (CellEntry::a, b), read with the entry
  };
  struct CellEntry {
    float mass;           // the node's probability of the cell
    std::int16_t a, b;    // the slopes of the density within the cell along xi and eta, x kHalfVectorSlopeUnit
  };
  // The cells' layout from the options: mirrored or not, the edges in cos theta_h and phi_h, the densities'
  // scales, the t lookup.
  void lay_out_cells();
  // The cell of h (in the nodes' frame) and h's coordinates xi, eta in it.
  int cell_of(const Eigen::Vector3d& h, double& xi, double& eta) const;
  // The cell index a draw's u1 in [0, 1] gives (before the alias table's choice) and the fraction f left of it.
  int cell_index(double u1, double& f) const {
    const double y = u1 * cells_;
    const int cell = std::min(static_cast<int>(y), cells_ - 1);
    f = y - cell;
    return cell;
  }
  double cell_area(int cell) const;
  // The masses m[cell] and node's slopes of the cells the horizon of w_r cuts (w_i: node's direction).
  void cut_cells(const Eigen::Vector3d& wi, const std::vector<int>& cut, const NonNegativeBrdf& fbar, double* m, int node);
  // The alias table of one node's probabilities p (cells values summing to 1).
  void build_alias(const double* p, AliasEntry* out) const;
  const CellEntry& entry(int node, int cell) const {
    return cells_of_nodes_[static_cast<size_t>(cell) * static_cast<size_t>(nodes()) + static_cast<size_t>(node)];
  }
  // The sum of the blend weights of the nodes that have mass (the draw and pdf() divide by it).
  double live_weight(const HalfVectorBlend& b) const;
  // The blended density of h at cell (xi, eta) in [0, 1]^2 [1/sr of h] times the weight of the live nodes
  // (callers divide by it; k: the cell's t bin; e[i]: the cell's entry of blend node i).
  double h_density(const HalfVectorBlend& b, const CellEntry* const* e, int k, double xi, double eta) const;

  HalfVectorTableOptions opt_;
  int cells_ = 0;
  bool mirrored_ = false;  // see HalfVectorTableOptions::mirror
  int phi_cells_ = 0;      // stored bins of phi_h: phi_bins, or phi_bins / 2 when mirrored
  double inv_phi_cells_ = 0.0;  // 1 / phi_cells_
  double phi_lo_ = 0.0;    // the lower edge of the first stored bin: -pi, or 0 when mirrored
  std::vector<double> cos_edge_;     // t_bins + 1 values of cos(theta_h) at the t edges
  std::vector<double> density_scale_;  // per t bin k: 1 / (the solid angle of its cells), halved when mirrored
  std::vector<double> phi_edge_cs_;  // phi_cells_ x (cos, sin) of phi_h at the lower edge of each stored bin
  std::vector<int> t_lookup_;        // kHalfVectorTLookup + 1 bins: the t bin at (1 - cos theta_h)^(1/4) = i / size
  std::vector<CellEntry> cells_of_nodes_;  // cells x nodes (cell-major); masses normalized per node
  std::vector<AliasEntry> alias_;    // cells x nodes (cell-major, as cells_of_nodes_)
  std::vector<double> albedo_;       // nodes
};

}  // namespace icobrdf
