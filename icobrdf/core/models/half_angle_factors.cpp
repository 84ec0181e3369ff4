#include "icobrdf/core/models/half_angle_factors.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <random>
#include <cmath>
#include <memory>
#include <sstream>
#include <utility>

#include "icobrdf/core/models/brdf_model.hpp"
#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/fast_atan2.hpp"
#include "icobrdf/core/support/select_without_branch.hpp"
#include "icobrdf/core/grid/gauss_legendre.hpp"
#include "icobrdf/core/basis/half_angle.hpp"

namespace icobrdf {

const char* half_angle_quantity_name(HalfAngleQuantity q) {
  return q == HalfAngleQuantity::F ? "f" : q == HalfAngleQuantity::Cosine ? "cosine" : "mean-cosine";
}

HalfAngleQuantity half_angle_quantity_from_name(const std::string& name) {
  if (name == "f") return HalfAngleQuantity::F;
  if (name == "cosine") return HalfAngleQuantity::Cosine;
  if (name == "mean-cosine") return HalfAngleQuantity::MeanCosine;
  throw ArgumentError("half-angle quantity: expected \"f\", \"cosine\" or \"mean-cosine\", got \"" + printable_text(name) + "\"");
}

const char* factor_precision_name(FactorPrecision p) {
  switch (p) {
    case FactorPrecision::Float64: return "float64";
    case FactorPrecision::Float32: return "float32";
    case FactorPrecision::Int16: return "int16";
    case FactorPrecision::Int8: return "int8";
  }
  return "float64";
}

FactorPrecision factor_precision_from_name(const std::string& name) {
  for (FactorPrecision p : {FactorPrecision::Float64, FactorPrecision::Float32, FactorPrecision::Int16, FactorPrecision::Int8})
    if (name == factor_precision_name(p)) return p;
  throw ArgumentError("factor precision: expected \"float64\", \"float32\", \"int16\" or \"int8\", got \"" + printable_text(name) + "\"");
}

int factor_precision_bytes(FactorPrecision p) {
  return p == FactorPrecision::Float64 ? 8 : p == FactorPrecision::Float32 ? 4 : p == FactorPrecision::Int16 ? 2 : 1;
}

int factor_precision_levels(FactorPrecision p) {
  return p == FactorPrecision::Int16 ? 32767 : p == FactorPrecision::Int8 ? 127 : 0;
}

std::size_t HalfAngleFactors::bytes() const {
  std::size_t n = 0, columns = 0;
  for (const auto& m : u) n += static_cast<std::size_t>(m.size()), columns += static_cast<std::size_t>(m.cols());
  for (const auto& m : v) n += static_cast<std::size_t>(m.size()), columns += static_cast<std::size_t>(m.cols());
  const std::size_t scales = factor_precision_levels(precision) > 0 ? 8 * columns : 0;
  return static_cast<std::size_t>(factor_precision_bytes(precision)) * n + scales + 8 * static_cast<std::size_t>(channel_scales.size());
}

double HalfAngleFactors::column_scale(const Eigen::Ref<const Eigen::VectorXd>& column, FactorPrecision p) {
  const int levels = factor_precision_levels(p);
  if (levels == 0 || column.size() == 0) return 0.0;
  // Rounded to a float: the largest value then maps to k = levels again, so that the scale of a quantized
  // column is the scale it was quantized with (quantize() is idempotent, a file's scale reproduces it).
  return static_cast<double>(static_cast<float>(column.cwiseAbs().maxCoeff() / levels));
}

void HalfAngleFactors::quantize() {
  const auto round_all = [this](std::vector<RowMatrixXd>& sets) {
    for (auto& m : sets) {
      if (precision == FactorPrecision::Float32) {
        m = m.cast<float>().cast<double>();
        continue;
      }
      if (precision == FactorPrecision::Float64) continue;
      for (Eigen::Index r = 0; r < m.cols(); ++r) {
        const double scale = column_scale(m.col(r), precision);
        const double levels = factor_precision_levels(precision);
        for (Eigen::Index i = 0; i < m.rows(); ++i)
          m(i, r) = scale > 0.0 ? scale * std::clamp(std::round(m(i, r) / scale), -levels, levels) : 0.0;
      }
    }
  };
  round_all(u);
  round_all(v);
}

double HalfAngleFactors::cosine_floor() const {
  return std::sin(0.5 * M_PI / (centred ? std::max(n_theta_d, 1) : std::max(n_theta_d - 1, 1)));
}

double HalfAngleFactors::node_t(int k) const { return centred ? (k + 0.5) / n_t : static_cast<double>(k) / (n_t - 1); }
double HalfAngleFactors::node_theta_d(int a) const {
  return 0.5 * M_PI * (centred ? (a + 0.5) / n_theta_d : static_cast<double>(a) / (n_theta_d - 1));
}
double HalfAngleFactors::node_phi_d(int b) const { return M_PI * (b + (centred ? 0.5 : 0.0)) / n_phi_d; }

void HalfAngleFactors::t_cell(int k, double& lo, double& hi) const {
  if (centred) {
    lo = static_cast<double>(k) / n_t, hi = (k + 1.0) / n_t;
    return;
  }
  const double dt = 1.0 / (n_t - 1);
  lo = std::max(0.0, (k - 0.5) * dt), hi = std::min(1.0, (k + 0.5) * dt);
}

void HalfAngleFactors::theta_d_cell(int a, double& lo, double& hi) const {
  if (centred) {
    lo = 0.5 * M_PI * a / n_theta_d, hi = 0.5 * M_PI * (a + 1.0) / n_theta_d;
    return;
  }
  const double dth = 0.5 * M_PI / (n_theta_d - 1);
  lo = std::max(0.0, (a - 0.5) * dth), hi = std::min(0.5 * M_PI, (a + 0.5) * dth);
}

double HalfAngleFactors::theta_h_of_t(double t) const {
  const double p = h_warp == 2.0 ? t * t : h_warp == 1.0 ? t : std::pow(t, h_warp);
  return 0.5 * M_PI * p;
}

namespace {
// t of theta_h on a grid of warp w (theta_h = (pi/2) t^w), inline in the per-pair code.
inline double warped_t_of_theta_h(double w, double theta_h) {
  const double x = std::clamp(theta_h * (2.0 / M_PI), 0.0, 1.0);
  return w == 2.0 ? std::sqrt(x) : w == 1.0 ? x : std::pow(x, 1.0 / w);
}
}  // namespace

double HalfAngleFactors::t_of_theta_h(double theta_h) const { return warped_t_of_theta_h(h_warp, theta_h); }

const char* horizon_corners_name(HorizonCorners c) { return c == HorizonCorners::All ? "all" : "valid"; }

HorizonCorners horizon_corners_from_name(const std::string& name) {
  if (name == "all") return HorizonCorners::All;
  if (name == "valid") return HorizonCorners::Valid;
  throw ArgumentError("horizon corners: expected \"all\" or \"valid\", got \"" + printable_text(name) + "\"");
}

Eigen::Vector3d HalfAngleFactors::h_of_grid_angles(double theta_h, double phi_h) const {
  const double st = std::sin(theta_h);
  const double a1 = h_scale_1 * st * std::cos(phi_h), a2 = h_scale_2 * st * std::sin(phi_h);
  const double c = std::cos(h_axis), s = std::sin(h_axis);
  return {c * a1 - s * a2, s * a1 + c * a2, std::cos(theta_h)};
}

// The stretch of a grid, precomputed for evaluation: rotation and inverse scales.
struct HalfAngleStretch {
  bool on = false;
  double c = 1, s = 0, inv1 = 1, inv2 = 1;
  explicit HalfAngleStretch(const HalfAngleFactors& F)
      : on(F.stretched()), c(std::cos(F.h_axis)), s(std::sin(F.h_axis)), inv1(1.0 / F.h_scale_1), inv2(1.0 / F.h_scale_2) {}
};

// The per-pair code of one kind of lobe (anisotropy, rank): f (or q) of the pair (wi, wr) into out[ch * stride].
using HalfAnglePairFn = void (*)(const HalfAngleFactors&, const HalfAnglePairContext&, const double* wi, const double* wr,
                                 double* out, Eigen::Index stride);
namespace {
HalfAnglePairFn pair_fn_for(const HalfAngleFactors& F);
}  // namespace

// What the evaluation of one pair needs besides the factors, computed once per batch (or per evaluator).
struct HalfAnglePairContext {
  HalfAngleStretch stretch;
  HalfAngleQuantity divide;
  double floor;
  bool drop;
  HalfAngleNodeTrig ht, dt;
  // Grid positions per radian (node k at position k + off): theta_d, phi_d, phi of the h grid; t per unit t.
  double off, t_scale, theta_d_scale, phi_d_scale, phi_h_scale;
  // The factor rows of each channel (u: h rows, v: d rows; R values per row), read without the vectors'
  // indirection on the per-pair path.
  std::vector<const double*> u_rows, v_rows;
  // Per-sample evaluators of isotropic grids with HorizonCorners::Valid: for each d node, the number of h
  // nodes k = 0, 1, ... that pair validly with it (node_pair_valid holds for k below it and fails from it on).
  // Empty in a batch, or where validity is not such a prefix in k (the corner test then runs on ht and dt,
  // which are kept only then).
  std::vector<std::int32_t> valid_h_count;
  int channels;
  HalfAnglePairFn pair_fn;  // the lobe's kind chosen once
  HalfAnglePairContext(const HalfAngleFactors& F, bool to_f, bool per_sample = false)
      : stretch(F), divide(to_f ? F.quantity : HalfAngleQuantity::F), floor(F.cosine_floor()),
        drop(F.corners == HorizonCorners::Valid), off(F.centred ? 0.5 : 0.0), t_scale(F.n_t - 1 + 2 * off),
        theta_d_scale((F.n_theta_d - 1 + 2 * off) / (0.5 * M_PI)), phi_d_scale(F.n_phi_d / M_PI),
        phi_h_scale(F.n_phi_h / (2.0 * M_PI)), channels(F.channels()), pair_fn(pair_fn_for(F)) {
    for (const auto& m : F.u) u_rows.push_back(m.data());
    for (const auto& m : F.v) v_rows.push_back(m.data());
    if (!drop) return;
    ht = half_angle_h_trig(F), dt = half_angle_d_trig(F);
    if (per_sample && F.isotropic) count_valid_h_nodes(F);
  }

 private:
  // valid_h_count by a scan over every node pair (once per evaluator: 65,536 pairs for a 64 x 64 x 16 lobe);
  // left empty when some d node's valid h nodes are not a prefix. With the counts the trig tables are not read
  // again, and are released (32 bytes per node: 0.5 MB for a MERL-sized lobe).
  void count_valid_h_nodes(const HalfAngleFactors& F) {
    valid_h_count.assign(static_cast<size_t>(F.d_nodes()), 0);
    for (int j = 0; j < F.d_nodes(); ++j) {
      int n = 0;
      while (n < F.n_t && node_pair_valid(ht, n, dt, j)) ++n;
      for (int k = n; k < F.n_t; ++k)
        if (node_pair_valid(ht, k, dt, j)) {
          valid_h_count.clear();
          return;
        }
      valid_h_count[static_cast<size_t>(j)] = n;
    }
    ht = HalfAngleNodeTrig{}, dt = HalfAngleNodeTrig{};
  }
};

namespace {

// Linear interpolation position on nodes 0..n-1 of x in [0, n-1] (clamped): lower node and fraction.
inline void clamped_cell(double x, int n, int& k, double& f) {
  x = std::clamp(x, 0.0, static_cast<double>(n - 1));
  k = std::min(static_cast<int>(x), n - 2);
  f = x - k;
}
// The same for a periodic coordinate x in [0, n] (n nodes): nodes k and k1 = k + 1 mod n.
inline void periodic_cell(double x, int n, int& k, int& k1, double& f) {
  if (x < 0.0) x += n;
  k = static_cast<int>(x);
  f = x - k;
  if (k >= n) {
    k -= n;
    if (k >= n) k = 0, f = 0.0;
  }
  k1 = k + 1 == n ? 0 : k + 1;
}

// Interpolation corners of one pair: h rows with weights, d rows with weights.
struct Corners {
  int h[4];
  double wh[4];
  int d[4];
  double wd[4];
};

// The grid angles of one pair without the frame's divisions. With s = w_i + w_r, m = w_i - w_r, rho = |s_xy|:
// theta_h = atan2(rho, s_z); theta_d = atan2(|m|, |s|) (w_i in the frame of h is (s' + m') / 2 with s' = (0, 0,
// |s|) and m' _|_ h for unit vectors, so |d_xy| = |m| / 2, d_z = |s| / 2); and phi_d from (X, Y) = 2 rho |s|
// (d_x, d_y), the rotation Ry(-theta_h) Rz(-phi_h) of m written out and multiplied by rho |s| > 0, which
// leaves the angle as it is:
//   X = s_z (s_x m_x + s_y m_y) - rho^2 m_z,   Y = |s| (s_x m_y - s_y m_x).
// The swap of w_i and w_r negates m, hence X and Y, exactly (each product and sum rounds symmetrically), so
// the canonical one of (X, Y) and (-X, -Y) keeps the evaluation bitwise reciprocal. At h = n (rho^2 below
// kTinyRho2, where the products would underflow) the frame is the identity, (X, Y) = (m_x, m_y). The three
// or four angles are independent chains of one square root and one fast_atan2 each.
constexpr double kTinyRho2 = 1e-280;

template <bool Aniso>
[[gnu::always_inline]] inline bool pair_corners(const HalfAngleFactors& F, const HalfAnglePairContext& X_, const double* wi, const double* wr, Corners& c) {
  const HalfAngleStretch& stretch = X_.stretch;
  if (wi[2] < -kHorizonSlack || wr[2] < -kHorizonSlack) return false;
  const double sx = wi[0] + wr[0], sy = wi[1] + wr[1], sz = wi[2] + wr[2];
  const double mx = wi[0] - wr[0], my = wi[1] - wr[1], mz = wi[2] - wr[2];
  const double rho2 = sx * sx + sy * sy, len = std::sqrt(rho2 + sz * sz);
  double X = mx, Y = my;
  if (rho2 >= kTinyRho2) {
    X = sz * (sx * mx + sy * my) - rho2 * mz, Y = len * (sx * my - sy * mx);
    if (Aniso) {  // the minimal-rotation frame: phi_d measured from the world's x axis (phi_d + phi_h)
      const double rx = sx * X - sy * Y, ry = sy * X + sx * Y;
      X = rx, Y = ry;
    }
  }
  // The canonical one of (X, Y) and (-X, -Y): phi_d in [0, pi] (without a branch: a coin toss per pair).
  const bool flip = Y < 0.0 || (Y == 0.0 && X < 0.0);
  X = select_without_branch(flip, -X, X), Y = select_without_branch(flip, -Y, Y);
  // Y >= 0 now, and both lengths are >= +0: the shorter atan2 forms, bitwise fast_atan2 here (but for a phi_d of
  // +0 where Y = -0, the same cell).
  const double theta_d = fast_atan2_first_quadrant(std::sqrt(mx * mx + my * my + mz * mz), len);
  const double phi_d = (X == 0.0 && Y == 0.0) ? 0.0 : fast_atan2_upper(Y, X);
  // The angles the h grid is laid out in: those of h, or of the stretched h' (s is a multiple of h).
  double theta_g, phi_g = 0.0;
  if (Aniso && stretch.on) {
    const double a1 = (stretch.c * sx + stretch.s * sy) * stretch.inv1, a2 = (stretch.c * sy - stretch.s * sx) * stretch.inv2;
    theta_g = fast_atan2_upper(std::sqrt(a1 * a1 + a2 * a2), sz);
    phi_g = (a1 == 0.0 && a2 == 0.0) ? 0.0 : fast_atan2(a2, a1);
  } else {
    theta_g = fast_atan2_upper(std::sqrt(rho2), sz);
    if (Aniso && rho2 > 0.0) phi_g = fast_atan2(sy, sx);
  }
  if (std::isnan(theta_d + phi_d + theta_g + phi_g)) return false;  // a non-finite direction (atan2 gives NaN, never inf)
  int k, a, b0, b1;
  double ft, fa, fb;
  const double off = X_.off;  // node k sits at (k + off) bin widths
  clamped_cell(warped_t_of_theta_h(F.h_warp, theta_g) * X_.t_scale - off, F.n_t, k, ft);
  clamped_cell(theta_d * X_.theta_d_scale - off, F.n_theta_d, a, fa);
  periodic_cell(phi_d * X_.phi_d_scale - off, F.n_phi_d, b0, b1, fb);
  c.d[0] = a * F.n_phi_d + b0, c.d[1] = a * F.n_phi_d + b1;
  c.d[2] = c.d[0] + F.n_phi_d, c.d[3] = c.d[1] + F.n_phi_d;
  c.wd[0] = (1 - fa) * (1 - fb), c.wd[1] = (1 - fa) * fb, c.wd[2] = fa * (1 - fb), c.wd[3] = fa * fb;
  if (Aniso) {
    int j0, j1;
    double fj;
    periodic_cell(phi_g * X_.phi_h_scale, F.n_phi_h, j0, j1, fj);
    c.h[0] = k * F.n_phi_h + j0, c.h[1] = k * F.n_phi_h + j1;
    c.h[2] = c.h[0] + F.n_phi_h, c.h[3] = c.h[1] + F.n_phi_h;
    c.wh[0] = (1 - ft) * (1 - fj), c.wh[1] = (1 - ft) * fj, c.wh[2] = ft * (1 - fj), c.wh[3] = ft * fj;
  } else {
    c.h[0] = k, c.h[1] = k + 1;
    c.wh[0] = 1 - ft, c.wh[1] = ft;
  }
  return true;
}

// Whether every corner pair of a cell is valid. Isotropic grids (phi_h = 0): validity, cos_h cos_d - sin_h
// sin_d |cos(phi_d)| >= -slack, falls with theta_h, theta_d in [0, pi/2] and with |cos(phi_d)|, and every
// rounded operation of node_pair_valid is monotone, so the corner of the larger theta_h (h[1]), the larger
// theta_d (row a + 1: d[2], d[3]) and the larger |cos(phi_d)| decides it exactly: the same answer as testing
// all 8 corners. Anisotropic grids (phi_h varies): sufficient only, the largest theta_h of its h corners plus
// the largest theta_d of its d corners is at most pi/2 (|cos(dphi)| <= 1).
template <bool Aniso>
inline bool all_corners_valid(const HalfAngleNodeTrig& ht, const HalfAngleNodeTrig& dt, const Corners& c) {
  if (!Aniso) return node_pair_valid(ht, c.h[1], dt, std::abs(dt.cp(c.d[2])) >= std::abs(dt.cp(c.d[3])) ? c.d[2] : c.d[3]);
  int hmax = c.h[Aniso ? 2 : 1];
  if (Aniso)
    for (int x : {0, 1, 3})
      if (ht.c(c.h[x]) < ht.c(hmax)) hmax = c.h[x];
  const int dmax = c.d[2];
  return ht.c(hmax) * dt.c(dmax) - ht.s(hmax) * dt.s(dmax) >= -kHorizonSlack;
}

// q at one pair from the corners that are node pairs on or above the horizon, their weights renormalized
// (HorizonCorners::Valid, for a pair whose cell straddles the horizon); 0 when no corner is valid.
template <bool Aniso>
void valid_corner_sum(const HalfAngleFactors& F, const Corners& c, const bool (&ok)[4][4], double scale, double* out,
                      Eigen::Index stride) {
  constexpr int nh = Aniso ? 4 : 2;
  const int R = F.rank;
  // Without branches on the corners (which corners are valid varies from pair to pair): the weights of the
  // invalid ones are 0; every corner's rows exist (cells are clamped inside the grid) and hold finite values.
  double w[nh][4], wsum = 0.0;
  for (int x = 0; x < nh; ++x)
    for (int y = 0; y < 4; ++y) wsum += w[x][y] = ok[x][y] ? c.wh[x] * c.wd[y] : 0.0;
  const double norm = wsum > 0.0 ? scale / wsum : 0.0;
  const bool shared = F.shared();
  for (int ch = 0; ch < F.channels(); ++ch) {
    const double* U = F.u[shared ? 0 : ch].data();
    const double* V = F.v[shared ? 0 : ch].data();
    const double* S = shared ? F.channel_scales.data() + static_cast<Eigen::Index>(ch) * R : nullptr;
    double q = 0.0;
    for (int r = 0; r < R; ++r) {
      const double vd[4] = {V[c.d[0] * R + r], V[c.d[1] * R + r], V[c.d[2] * R + r], V[c.d[3] * R + r]};
      double t = 0.0;
      for (int x = 0; x < nh; ++x)
        t += U[c.h[x] * R + r] * (w[x][0] * vd[0] + w[x][1] * vd[1] + w[x][2] * vd[2] + w[x][3] * vd[3]);
      q += S ? S[r] * t : t;
    }
    out[ch * stride] = q * norm;
  }
}

// q of every channel from its own factors (not shared): out[ch * stride] = scale sum_r uh_r vd_r, with the
// corners' rows (each holds its R terms side by side). kRank > 0: R = kRank known at compile time; 0: any R.
template <bool Aniso, int kRank>
inline void channel_sums(const HalfAngleFactors& F, const HalfAnglePairContext& X, const Corners& c, double scale, int channels,
                         double* out, Eigen::Index stride) {
  const int R = kRank > 0 ? kRank : F.rank;
  const double* const* Us = X.u_rows.data();
  const double* const* Vs = X.v_rows.data();
  for (int ch = 0; ch < channels; ++ch) {
    const double* U = Us[ch];
    const double* V = Vs[ch];
    const double *u0 = U + c.h[0] * R, *u1 = U + c.h[1] * R, *u2 = U + c.h[Aniso ? 2 : 0] * R, *u3 = U + c.h[Aniso ? 3 : 0] * R;
    const double *v0 = V + c.d[0] * R, *v1 = V + c.d[1] * R, *v2 = V + c.d[2] * R, *v3 = V + c.d[3] * R;
    double q = 0.0;
    for (int r = 0; r < R; ++r) {
      double uh = c.wh[0] * u0[r] + c.wh[1] * u1[r];
      if (Aniso) uh += c.wh[2] * u2[r] + c.wh[3] * u3[r];
      q += uh * (c.wd[0] * v0[r] + c.wd[1] * v1[r] + c.wd[2] * v2[r] + c.wd[3] * v3[r]);
    }
    out[ch * stride] = q * scale;
  }
}

// A pair whose cell the horizon may cut (all_corners_valid false): the sum over its valid corners when some
// corner is invalid (true), else false. Out of line: the few pairs near the horizon take it, and inlined it
// enlarged the common path's stack frame and code.
template <bool Aniso>
[[gnu::noinline]] bool horizon_cell_sum(const HalfAngleFactors& F, const HalfAnglePairContext& X, const Corners& c, double scale,
                                        double* out, Eigen::Index stride) {
  bool ok[4][4], all = true;
  for (int x = 0; x < (Aniso ? 4 : 2); ++x)
    for (int y = 0; y < 4; ++y) all &= ok[x][y] = node_pair_valid(X.ht, c.h[x], X.dt, c.d[y]);
  if (all) return false;
  valid_corner_sum<Aniso>(F, c, ok, scale, out, stride);
  return true;
}

// An isotropic cell with a corner below the horizon, decided by the per-d-node counts of valid h nodes: the sum
// over its valid corners. Out of line, as horizon_cell_sum.
[[gnu::noinline]] void counted_horizon_cell_sum(const HalfAngleFactors& F, const HalfAnglePairContext& X, const Corners& c,
                                                double scale, double* out, Eigen::Index stride) {
  const std::int32_t* n = X.valid_h_count.data();
  bool ok[4][4] = {};
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y < 4; ++y) ok[x][y] = c.h[x] < n[c.d[y]];
  valid_corner_sum<false>(F, c, ok, scale, out, stride);
}

// HorizonCorners::Valid: true when the cell has a corner below the horizon and out holds the sum over its
// valid corners; false when every corner is valid.
template <bool Aniso>
inline bool horizon_cut_sum(const HalfAngleFactors& F, const HalfAnglePairContext& X, const Corners& c, double scale, double* out,
                            Eigen::Index stride) {
  if (!Aniso && !X.valid_h_count.empty()) {
    // The corners' h nodes are k = c.h[0] and k + 1 = c.h[1]: all eight are valid when every d corner has
    // more than k + 1 valid h nodes.
    const std::int32_t* n = X.valid_h_count.data();
    if (std::min(std::min(n[c.d[0]], n[c.d[1]]), std::min(n[c.d[2]], n[c.d[3]])) > c.h[1]) return false;
    counted_horizon_cell_sum(F, X, c, scale, out, stride);
    return true;
  }
  return !all_corners_valid<Aniso>(X.ht, X.dt, c) && horizon_cell_sum<Aniso>(F, X, c, scale, out, stride);
}

// f (or q) of one pair: out[ch * stride] for every channel. kRank: the rank of non-shared factors when it is
// 1-4, known at compile time (the term loop unrolled: the general loop's vectorization checks cost more
// instructions than two to four terms take, 629 -> 590 per pair of a rank-2 lobe counted by callgrind); 0 for
// any other rank and for shared factors.
template <bool Aniso, int kRank>
void eval_pair_ranked(const HalfAngleFactors& F, const HalfAnglePairContext& X, const double* wi, const double* wr, double* out,
                      Eigen::Index stride) {
  const int channels = X.channels;
  Corners c;
  if (!pair_corners<Aniso>(F, X, wi, wr, c)) {
    for (int ch = 0; ch < channels; ++ch) out[ch * stride] = 0.0;
    return;
  }
  const double scale = X.divide == HalfAngleQuantity::Cosine ? 1.0 / (std::max(wi[2], X.floor) * std::max(wr[2], X.floor))
                       : X.divide == HalfAngleQuantity::MeanCosine ? 1.0 / std::max(0.5 * (wi[2] + wr[2]), X.floor)
                                                                 : 1.0;
  if (X.drop && horizon_cut_sum<Aniso>(F, X, c, scale, out, stride)) return;
  if (kRank == 0 && F.shared()) {  // the terms once, then each channel's weights
    const int R = F.rank;
    double term[kMaxStoredRank];
    const double* U = X.u_rows[0];
    const double* V = X.v_rows[0];
    for (int r = 0; r < R; ++r) {
      double uh = c.wh[0] * U[c.h[0] * R + r] + c.wh[1] * U[c.h[1] * R + r];
      if (Aniso) uh += c.wh[2] * U[c.h[2] * R + r] + c.wh[3] * U[c.h[3] * R + r];
      term[r] = uh * (c.wd[0] * V[c.d[0] * R + r] + c.wd[1] * V[c.d[1] * R + r] + c.wd[2] * V[c.d[2] * R + r] +
                      c.wd[3] * V[c.d[3] * R + r]);
    }
    for (int ch = 0; ch < channels; ++ch) {
      const double* S = F.channel_scales.data() + static_cast<Eigen::Index>(ch) * R;
      double q = 0.0;
      for (int r = 0; r < R; ++r) q += S[r] * term[r];
      out[ch * stride] = q * scale;
    }
    return;
  }
  channel_sums<Aniso, kRank>(F, X, c, scale, channels, out, stride);
}

// The per-pair function for a lobe: its anisotropy and rank decided once, not per pair.
template <bool Aniso>
HalfAnglePairFn pair_fn_for_rank(const HalfAngleFactors& F) {
  switch (F.shared() ? 0 : F.rank) {
    case 1: return eval_pair_ranked<Aniso, 1>;
    case 2: return eval_pair_ranked<Aniso, 2>;
    case 3: return eval_pair_ranked<Aniso, 3>;
    case 4: return eval_pair_ranked<Aniso, 4>;
    default: return eval_pair_ranked<Aniso, 0>;
  }
}

HalfAnglePairFn pair_fn_for(const HalfAngleFactors& F) { return F.isotropic ? pair_fn_for_rank<false>(F) : pair_fn_for_rank<true>(F); }

void eval_rows(const HalfAngleFactors& F, const RowMatrix3d& wi, const RowMatrix3d& wr, bool to_f, Eigen::Ref<Eigen::MatrixXd> out) {
  const Eigen::Index rows = wi.rows();
  const HalfAnglePairContext X(F, to_f);
  const HalfAnglePairFn pair = X.pair_fn;
  const Eigen::Index stride = out.outerStride();
#pragma omp parallel for schedule(static) if (rows > 2048)
  for (Eigen::Index i = 0; i < rows; ++i) pair(F, X, wi.data() + 3 * i, wr.data() + 3 * i, out.data() + i, stride);
}

}  // namespace

namespace {

// True angles of h node `row` (those of the node's h, not of h' on a stretched grid; phi_h = 0 at h = n keeps
// the node's own phi_h, where the rotation it enters is the identity).
void h_node_angles(const HalfAngleFactors& g, int row, double& th, double& ph) {
  const int k = row / g.n_phi_h, j = row % g.n_phi_h;
  th = g.theta_h_of_t(g.node_t(k));
  ph = 2.0 * M_PI * j / g.n_phi_h;
  if (!g.stretched()) return;
  const Eigen::Vector3d h = g.h_of_grid_angles(th, ph);
  th = std::atan2(std::hypot(h.x(), h.y()), h.z());
  if (h.x() != 0.0 || h.y() != 0.0) ph = std::atan2(h.y(), h.x());
}

// sin and cos of the angles angle(row, theta, phi) gives for rows 0..n-1.
template <class Angles>
HalfAngleNodeTrig trig_table(int n, Angles angles) {
  HalfAngleNodeTrig t;
  t.m.resize(n, 4);
  for (int i = 0; i < n; ++i) {
    double th, ph;
    angles(i, th, ph);
    t.m.row(i) << std::sin(th), std::cos(th), std::cos(ph), std::sin(ph);
  }
  return t;
}

// The same for a grid whose node angles are separable, row a * phi.size() + b at (theta[a], phi[b]): the sines
// and cosines of the two lists are taken once (every evaluation with HorizonCorners::Valid builds these
// tables; a MERL lobe has 16,200 d nodes but 90 + 180 angles).
HalfAngleNodeTrig separable_trig_table(const std::vector<double>& theta, const std::vector<double>& phi) {
  const auto na = static_cast<Eigen::Index>(theta.size()), nb = static_cast<Eigen::Index>(phi.size());
  Eigen::ArrayXd st(na), ct(na), sp(nb), cp(nb);
  for (Eigen::Index a = 0; a < na; ++a) st(a) = std::sin(theta[a]), ct(a) = std::cos(theta[a]);
  for (Eigen::Index b = 0; b < nb; ++b) sp(b) = std::sin(phi[b]), cp(b) = std::cos(phi[b]);
  HalfAngleNodeTrig t;
  t.m.resize(na * nb, 4);
  for (Eigen::Index a = 0; a < na; ++a)
    for (Eigen::Index b = 0; b < nb; ++b) t.m.row(a * nb + b) << st(a), ct(a), cp(b), sp(b);
  return t;
}

}  // namespace

HalfAngleNodeTrig half_angle_h_trig(const HalfAngleFactors& g) {
  if (g.stretched())  // the true angles of a stretched grid's nodes are not separable
    return trig_table(g.h_nodes(), [&g](int i, double& th, double& ph) { h_node_angles(g, i, th, ph); });
  std::vector<double> theta(static_cast<size_t>(g.n_t)), phi(static_cast<size_t>(g.n_phi_h));
  for (int k = 0; k < g.n_t; ++k) theta[static_cast<size_t>(k)] = g.theta_h_of_t(g.node_t(k));
  for (int j = 0; j < g.n_phi_h; ++j) phi[static_cast<size_t>(j)] = 2.0 * M_PI * j / g.n_phi_h;
  return separable_trig_table(theta, phi);
}

HalfAngleNodeTrig half_angle_d_trig(const HalfAngleFactors& g) {
  std::vector<double> theta(static_cast<size_t>(g.n_theta_d)), phi(static_cast<size_t>(g.n_phi_d));
  for (int a = 0; a < g.n_theta_d; ++a) theta[static_cast<size_t>(a)] = g.node_theta_d(a);
  for (int b = 0; b < g.n_phi_d; ++b) phi[static_cast<size_t>(b)] = g.node_phi_d(b);
  return separable_trig_table(theta, phi);
}

namespace {

void eval_impl(const HalfAngleFactors& F, const RowMatrix3d& wi, const RowMatrix3d& wr, bool to_f,
               Eigen::Ref<Eigen::MatrixXd> out) {
  check_pair_shapes(wi, wr, out, F.channels());
  eval_rows(F, wi, wr, to_f, out);
}

}  // namespace

void HalfAngleFactors::eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const {
  eval_impl(*this, wi, wr, true, out);
}

Eigen::MatrixXd HalfAngleFactors::eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const {
  Eigen::MatrixXd out(wi.rows(), channels());
  eval(wi, wr, out);
  return out;
}

HalfAnglePairEvaluator::HalfAnglePairEvaluator(std::shared_ptr<const HalfAngleFactors> lobe) : lobe_(std::move(lobe)) {
  if (!lobe_) throw ArgumentError("HalfAnglePairEvaluator: no lobe");
  context_ = std::make_shared<const HalfAnglePairContext>(*lobe_, true, true);
}

void HalfAnglePairEvaluator::eval(const double* wi, const double* wr, double* out) const {
  context_->pair_fn(*lobe_, *context_, wi, wr, out, 1);
}

void HalfAngleFactors::eval_quantity(const RowMatrix3d& wi, const RowMatrix3d& wr,
                                     Eigen::Ref<Eigen::MatrixXd> out) const {
  eval_impl(*this, wi, wr, false, out);
}

void HalfAngleFactors::validate() const {
  const auto fail = [](const std::string& what) { throw InputError("half-angle factors: " + what); };
  const auto num = [](double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  };
  if (n_t < 2) fail("n_t = " + num(n_t) + ", expected >= 2");
  if (n_theta_d < 2) fail("n_theta_d = " + num(n_theta_d) + ", expected >= 2");
  if (n_phi_d < 1) fail("n_phi_d = " + num(n_phi_d) + ", expected >= 1");
  if (isotropic && n_phi_h != 1) fail("n_phi_h = " + num(n_phi_h) + " for an isotropic representation, expected 1");
  if (n_phi_h < 1) fail("n_phi_h = " + num(n_phi_h) + ", expected >= 1");
  if (!(h_warp >= 0.25 && h_warp <= 8.0)) fail("h_warp = " + num(h_warp) + ", expected in [0.25, 8]");
  if (isotropic && stretched()) fail("an isotropic representation with a stretched h grid, expected h_axis = 0, scales 1");
  if (!(std::abs(h_axis) <= M_PI)) fail("h_axis = " + num(h_axis) + ", expected in [-pi, pi]");
  for (double k : {h_scale_1, h_scale_2})
    if (!(k >= kMinHScale && k <= kMaxHScale))
      fail("h scale " + num(k) + ", expected in [" + num(kMinHScale) + ", " + num(kMaxHScale) + "]");
  if (rank < 0) fail("rank = " + num(rank) + ", expected >= 0");
  if (u.empty()) fail("no channels");
  if (shared()) {
    if (u.size() != 1 || v.size() != 1) fail(num(u.size()) + " u and " + num(v.size()) + " v factor sets with channel scales, expected 1 each");
    if (channel_scales.cols() != rank) fail("channel scales of " + num(channel_scales.cols()) + " terms, expected rank " + num(rank));
    if (rank > kMaxStoredRank) fail("rank " + num(rank) + " with shared factors, expected <= " + num(kMaxStoredRank));
    if (!channel_scales.allFinite()) fail("channel scales have a non-finite value");
  }
  if (u.size() != v.size()) fail(num(u.size()) + " u factors but " + num(v.size()) + " v factors");
  for (std::size_t c = 0; c < u.size(); ++c) {
    const std::string ch = " of channel " + num(c);
    if (u[c].rows() != h_nodes() || u[c].cols() != rank)
      fail("u" + ch + " is " + num(u[c].rows()) + " x " + num(u[c].cols()) + ", expected " + num(h_nodes()) + " x " +
           num(rank));
    if (v[c].rows() != d_nodes() || v[c].cols() != rank)
      fail("v" + ch + " is " + num(v[c].rows()) + " x " + num(v[c].cols()) + ", expected " + num(d_nodes()) + " x " +
           num(rank));
    if (!u[c].allFinite()) fail("u" + ch + " has a non-finite value");
    if (!v[c].allFinite()) fail("v" + ch + " has a non-finite value");
  }
}

Eigen::VectorXd half_angle_h_weights(const HalfAngleFactors& g) {
  // Dual cell [t_lo, t_hi] of t_k; integral of sin(theta) dtheta dphi = cos(th_lo) - cos(th_hi) per radian
  // of phi, written as 2 sin(mean) sin(half difference) (no cancellation near the pole).
  Eigen::VectorXd a(g.h_nodes());
  const double dphi = 2.0 * M_PI / g.n_phi_h;
  for (int k = 0; k < g.n_t; ++k) {
    double tlo, thi;
    g.t_cell(k, tlo, thi);
    const double lo = g.theta_h_of_t(tlo), hi = g.theta_h_of_t(thi);
    const double w = dphi * 2.0 * std::sin(0.5 * (hi + lo)) * std::sin(0.5 * (hi - lo));
    for (int j = 0; j < g.n_phi_h; ++j) a(k * g.n_phi_h + j) = w;
    if (!g.stretched()) continue;
    // dw_h = J dw_h' (see the header); Gauss-Legendre points over the cell of h'. Near the horizon J peaks
    // in phi_h' (as (s1^2 cos^2 + s2^2 sin^2)^-3/2): 8 x 8 points integrate a 3:1 stretch on 8 phi cells to
    // 3e-5 of 2 pi where 4 x 4 left 1e-2 (measured, 12 x 8 cells).
    constexpr int kStretchRule = 8;
    const QuadratureRule rt = gauss_legendre(kStretchRule, lo, hi);
    for (int j = 0; j < g.n_phi_h; ++j) {
      const double p0 = 2.0 * M_PI * j / g.n_phi_h;
      const QuadratureRule rp = gauss_legendre(kStretchRule, p0 - 0.5 * dphi, p0 + 0.5 * dphi);
      double sum = 0.0;
      for (int x = 0; x < kStretchRule; ++x)
        for (int y = 0; y < kStretchRule; ++y) {
          const double n = g.h_of_grid_angles(rt.nodes[x], rp.nodes[y]).norm();
          sum += rt.weights[x] * rp.weights[y] * std::sin(rt.nodes[x]) * g.h_scale_1 * g.h_scale_2 / (n * n * n);
        }
      a(k * g.n_phi_h + j) = sum;
    }
  }
  return a;
}

Eigen::VectorXd half_angle_d_weights(const HalfAngleFactors& g) {
  // integral of 4 cos(t) sin(t) dt = 2 (sin^2 hi - sin^2 lo) = 2 sin(hi + lo) sin(hi - lo); phi_d in
  // [0, pi) stands for both copies of [0, 2 pi): 2 x pi / n_phi_d.
  Eigen::VectorXd b(g.d_nodes());
  const double dphi = 2.0 * M_PI / g.n_phi_d;
  for (int a = 0; a < g.n_theta_d; ++a) {
    double lo, hi;
    g.theta_d_cell(a, lo, hi);
    const double w = dphi * 2.0 * std::sin(hi + lo) * std::sin(hi - lo);
    for (int j = 0; j < g.n_phi_d; ++j) b(a * g.n_phi_d + j) = w;
  }
  return b;
}

void half_angle_node_pair(const HalfAngleFactors& g, int h_row, int d_row, Eigen::Vector3d& wi,
                          Eigen::Vector3d& wr) {
  // Built from the node angles (not from h), so that the nodes at t = 0 keep their phi_h: they are the
  // limits h -> n along that azimuth.
  const int a = d_row / g.n_phi_d, b = d_row % g.n_phi_d;
  double th, ph;
  h_node_angles(g, h_row, th, ph);
  // Anisotropic grids measure phi_d in the minimal-rotation frame (phi_d + phi_h): back to Rusinkiewicz's.
  const double td = g.node_theta_d(a), pd = g.node_phi_d(b) - (g.isotropic ? 0.0 : ph);
  const double sd = std::sin(td);
  const Eigen::Vector3d d(sd * std::cos(pd), sd * std::sin(pd), std::cos(td));
  const double ct = std::cos(th), st = std::sin(th), c = std::cos(ph), s = std::sin(ph);
  const auto back = [&](double x, double y, double z) {
    const double X = ct * x + st * z, Z = -st * x + ct * z;
    return Eigen::Vector3d(c * X - s * y, s * X + c * y, Z);
  };
  wi = back(d.x(), d.y(), d.z());
  wr = back(-d.x(), -d.y(), d.z());
}

}  // namespace icobrdf
