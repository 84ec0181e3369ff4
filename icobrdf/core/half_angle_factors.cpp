#include "icobrdf/core/half_angle_factors.hpp"

#include <Eigen/Dense>
#include <omp.h>

#include <algorithm>
#include <mutex>
#include <chrono>
#include <random>
#include <cmath>
#include <sstream>

#include "icobrdf/core/brdf_model.hpp"
#include "icobrdf/core/direction.hpp"
#include "icobrdf/core/error.hpp"
#include "icobrdf/core/fast_atan2.hpp"
#include "icobrdf/core/gauss_legendre.hpp"
#include "icobrdf/core/half_angle.hpp"

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

PairSampler model_pair_sampler(const BrdfModel& model) {
  return [&model](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
    model.eval(wi, wr, out);
  };
}

void uniform_pairs(int n, std::uint64_t seed, RowMatrix3d& wi, RowMatrix3d& wr) {
  std::mt19937_64 rng(seed);
  wi.resize(n, 3);
  wr.resize(n, 3);
  for (int k = 0; k < n; ++k) {
    wi.row(k) = uniform_direction(rng).transpose();
    wr.row(k) = uniform_direction(rng).transpose();
  }
}

std::size_t HalfAngleFactors::bytes() const {
  std::size_t n = 0;
  for (const auto& m : u) n += static_cast<std::size_t>(m.size());
  for (const auto& m : v) n += static_cast<std::size_t>(m.size());
  return 8 * n;
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

double HalfAngleFactors::t_of_theta_h(double theta_h) const {
  const double x = std::clamp(theta_h / (0.5 * M_PI), 0.0, 1.0);
  return h_warp == 2.0 ? std::sqrt(x) : h_warp == 1.0 ? x : std::pow(x, 1.0 / h_warp);
}

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

namespace {

// The stretch of a grid, precomputed for evaluation: rotation and inverse scales.
struct HStretch {
  bool on = false;
  double c = 1, s = 0, inv1 = 1, inv2 = 1;
  explicit HStretch(const HalfAngleFactors& F)
      : on(F.stretched()), c(std::cos(F.h_axis)), s(std::sin(F.h_axis)), inv1(1.0 / F.h_scale_1), inv2(1.0 / F.h_scale_2) {}
};

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

template <bool Aniso>
inline bool pair_corners(const HalfAngleFactors& F, const HStretch& stretch, const double* wi, const double* wr, Corners& c) {
  if (wi[2] < -kHorizonSlack || wr[2] < -kHorizonSlack) return false;
  const double sx = wi[0] + wr[0], sy = wi[1] + wr[1], sz = wi[2] + wr[2];
  const double mx = wi[0] - wr[0], my = wi[1] - wr[1], mz = wi[2] - wr[2];
  const HalfAngleFrame fr = half_angle_frame(sx, sy, sz);
  const double xp = fr.c * mx + fr.sn * my, yp = -fr.sn * mx + fr.c * my;
  double dx = fr.ct * xp - fr.st * mz, dy = yp;
  if (Aniso) {  // the minimal-rotation frame: phi_d measured from the world's x axis (phi_d + phi_h)
    const double rx = fr.c * dx - fr.sn * dy, ry = fr.sn * dx + fr.c * dy;
    dx = rx, dy = ry;
  }
  // The swap negates (dx, dy) exactly: use the canonical one of the two (phi_d in [0, pi]).
  if (dy < 0.0 || (dy == 0.0 && dx < 0.0)) dx = -dx, dy = -dy;
  const double theta_d = fast_atan2(std::sqrt(dx * dx + dy * dy), fr.len);  // len = 2 d_z, (dx, dy) = 2 d_xy
  const double phi_d = (dx == 0.0 && dy == 0.0) ? 0.0 : fast_atan2(dy, dx);
  // The angles the h grid is laid out in: those of h, or of the stretched h' (s = w_i + w_r is a multiple of h).
  double theta_g, phi_g = 0.0;
  if (Aniso && stretch.on) {
    const double a1 = (stretch.c * sx + stretch.s * sy) * stretch.inv1, a2 = (stretch.c * sy - stretch.s * sx) * stretch.inv2;
    theta_g = fast_atan2(std::sqrt(a1 * a1 + a2 * a2), sz);
    phi_g = (a1 == 0.0 && a2 == 0.0) ? 0.0 : fast_atan2(a2, a1);
  } else {
    theta_g = fast_atan2(fr.st, fr.ct);
    if (Aniso && fr.st > 0.0) phi_g = fast_atan2(fr.sn, fr.c);
  }
  int k, a, b0, b1;
  double ft, fa, fb;
  const double off = F.centred ? 0.5 : 0.0;  // node k sits at (k + off) bin widths
  clamped_cell(F.t_of_theta_h(theta_g) * (F.n_t - 1 + 2 * off) - off, F.n_t, k, ft);
  clamped_cell(theta_d * ((F.n_theta_d - 1 + 2 * off) / (0.5 * M_PI)) - off, F.n_theta_d, a, fa);
  periodic_cell(phi_d * (F.n_phi_d / M_PI) - off, F.n_phi_d, b0, b1, fb);
  c.d[0] = a * F.n_phi_d + b0, c.d[1] = a * F.n_phi_d + b1;
  c.d[2] = c.d[0] + F.n_phi_d, c.d[3] = c.d[1] + F.n_phi_d;
  c.wd[0] = (1 - fa) * (1 - fb), c.wd[1] = (1 - fa) * fb, c.wd[2] = fa * (1 - fb), c.wd[3] = fa * fb;
  if (Aniso) {
    int j0, j1;
    double fj;
    periodic_cell(phi_g * (F.n_phi_h / (2.0 * M_PI)), F.n_phi_h, j0, j1, fj);
    c.h[0] = k * F.n_phi_h + j0, c.h[1] = k * F.n_phi_h + j1;
    c.h[2] = c.h[0] + F.n_phi_h, c.h[3] = c.h[1] + F.n_phi_h;
    c.wh[0] = (1 - ft) * (1 - fj), c.wh[1] = (1 - ft) * fj, c.wh[2] = ft * (1 - fj), c.wh[3] = ft * fj;
  } else {
    c.h[0] = k, c.h[1] = k + 1;
    c.wh[0] = 1 - ft, c.wh[1] = ft;
  }
  return true;
}

// q at one pair from the corners that are node pairs on or above the horizon, their weights renormalized
// (HorizonCorners::Valid, for a pair whose cell straddles the horizon); 0 when no corner is valid.
// Sufficient for every corner pair of a cell to be valid: the largest theta_h of its h corners plus the
// largest theta_d of its d corners (rows a + 1) is at most pi/2, i.e. cos of the sum >= -slack (validity
// needs cos_h cos_d - sin_h sin_d |cos(dphi)| >= -slack, and |cos(dphi)| <= 1).
template <bool Aniso>
inline bool all_corners_valid(const HalfAngleNodeTrig& ht, const HalfAngleNodeTrig& dt, const Corners& c) {
  int hmax = c.h[Aniso ? 2 : 1];
  if (Aniso)
    for (int x : {0, 1, 3})
      if (ht.c(c.h[x]) < ht.c(hmax)) hmax = c.h[x];
  const int dmax = c.d[2];
  return ht.c(hmax) * dt.c(dmax) - ht.s(hmax) * dt.s(dmax) >= -kHorizonSlack;
}

template <bool Aniso>
void valid_corner_sum(const HalfAngleFactors& F, const Corners& c, const bool (&ok)[4][4], Eigen::Index i, double scale,
                      Eigen::Ref<Eigen::MatrixXd> out) {
  const int R = F.rank, nh = Aniso ? 4 : 2;
  double wsum = 0.0;
  for (int x = 0; x < nh; ++x)
    for (int y = 0; y < 4; ++y)
      if (ok[x][y]) wsum += c.wh[x] * c.wd[y];
  for (int ch = 0; ch < F.channels(); ++ch) {
    const double* U = F.u[ch].data();
    const double* V = F.v[ch].data();
    double q = 0.0;
    for (int x = 0; x < nh; ++x)
      for (int y = 0; y < 4; ++y) {
        if (!ok[x][y] || c.wh[x] * c.wd[y] == 0.0) continue;
        double uv = 0.0;
        for (int r = 0; r < R; ++r) uv += U[c.h[x] * R + r] * V[c.d[y] * R + r];
        q += c.wh[x] * c.wd[y] * uv;
      }
    out(i, ch) = wsum > 0.0 ? q / wsum * scale : 0.0;
  }
}

template <bool Aniso>
void eval_rows(const HalfAngleFactors& F, const RowMatrix3d& wi, const RowMatrix3d& wr, bool to_f,
               Eigen::Ref<Eigen::MatrixXd> out) {
  const HalfAngleQuantity divide = to_f ? F.quantity : HalfAngleQuantity::F;
  const double floor = F.cosine_floor();
  const Eigen::Index rows = wi.rows();
  const int R = F.rank, channels = F.channels();
  const HStretch stretch(F);
  const bool drop = F.corners == HorizonCorners::Valid;
  HalfAngleNodeTrig ht, dt;
  if (drop) ht = half_angle_h_trig(F), dt = half_angle_d_trig(F);
#pragma omp parallel for schedule(static) if (rows > 2048)
  for (Eigen::Index i = 0; i < rows; ++i) {
    Corners c;
    if (!pair_corners<Aniso>(F, stretch, wi.data() + 3 * i, wr.data() + 3 * i, c)) {
      for (int ch = 0; ch < channels; ++ch) out(i, ch) = 0.0;
      continue;
    }
    const double scale = divide == HalfAngleQuantity::Cosine ? 1.0 / (std::max(wi(i, 2), floor) * std::max(wr(i, 2), floor))
                         : divide == HalfAngleQuantity::MeanCosine ? 1.0 / std::max(0.5 * (wi(i, 2) + wr(i, 2)), floor)
                                                                   : 1.0;
    if (drop && !all_corners_valid<Aniso>(ht, dt, c)) {
      bool ok[4][4], all = true;
      for (int x = 0; x < (Aniso ? 4 : 2); ++x)
        for (int y = 0; y < 4; ++y) all &= ok[x][y] = node_pair_valid(ht, c.h[x], dt, c.d[y]);
      if (!all) {
        valid_corner_sum<Aniso>(F, c, ok, i, scale, out);
        continue;
      }
    }
    for (int ch = 0; ch < channels; ++ch) {
      const double* U = F.u[ch].data();
      const double* V = F.v[ch].data();
      double q = 0.0;
      for (int r = 0; r < R; ++r) {
        double uh = c.wh[0] * U[c.h[0] * R + r] + c.wh[1] * U[c.h[1] * R + r];
        if (Aniso) uh += c.wh[2] * U[c.h[2] * R + r] + c.wh[3] * U[c.h[3] * R + r];
        const double vd = c.wd[0] * V[c.d[0] * R + r] + c.wd[1] * V[c.d[1] * R + r] + c.wd[2] * V[c.d[2] * R + r] +
                          c.wd[3] * V[c.d[3] * R + r];
        q += uh * vd;
      }
      out(i, ch) = q * scale;
    }
  }
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
  if (F.isotropic)
    eval_rows<false>(F, wi, wr, to_f, out);
  else
    eval_rows<true>(F, wi, wr, to_f, out);
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

namespace {

// Weighted ALS for one channel: minimizes sum W (Q - U V^T)^2 with W = 0 at missing nodes.
struct AlsProblem {
  const Eigen::MatrixXd& W;   // H x D, fitting weights (valid nodes and weighted extension)
  const Eigen::MatrixXd& WQ;  // W .* Q
  const Eigen::MatrixXd& Wv;  // weights of the valid nodes only (the error measure)
  double norm2;               // sum Wv Q^2
};

// sum Wv (Q - U V^T)^2 (the error) and sum W (Q - U V^T)^2 (the objective).
std::pair<double, double> weighted_error2(const AlsProblem& p, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& U,
                                          const Eigen::MatrixXd& V) {
  Eigen::MatrixXd E = Q;
  if (U.cols() > 0) E.noalias() -= U * V.transpose();
  E = E.array().square();
  return {(p.Wv.array() * E.array()).sum(), (p.W.array() * E.array()).sum()};
}

// New rows X (n x R) minimizing sum_j Wt(i, j) (T(i, j) - X_i . Y_j)^2 for every i, given Y (m x R).
// Wt is W or W^T, WT = Wt .* T.
template <class WMat, class WQMat>
Eigen::MatrixXd solve_side(const WMat& Wt, const WQMat& WT, const Eigen::MatrixXd& Y) {
  const int R = static_cast<int>(Y.cols());
  const int P = R * (R + 1) / 2;
  Eigen::MatrixXd YY(Y.rows(), P);
  for (int r = 0, p = 0; r < R; ++r)
    for (int s = r; s < R; ++s, ++p) YY.col(p) = Y.col(r).cwiseProduct(Y.col(s));
  const Eigen::MatrixXd A = Wt * YY;  // n x P
  const Eigen::MatrixXd B = WT * Y;   // n x R
  Eigen::MatrixXd X(A.rows(), R);
  // Serial: each row is an R x R solve (~0.1-1 us); a parallel region here cost 25x the whole fit on a loaded
  // 2-core machine (threads waiting at the barrier behind other processes), and the products above thread.
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxFitRank, kMaxFitRank>;
  for (Eigen::Index i = 0; i < A.rows(); ++i) {
    Small N(R, R);
    for (int r = 0, p = 0; r < R; ++r)
      for (int s = r; s < R; ++s, ++p) N(r, s) = N(s, r) = A(i, p);
    const double tr = N.trace();
    if (!(tr > 0.0)) {
      X.row(i).setZero();
      continue;
    }
    N.diagonal().array() += 1e-14 * tr;
    X.row(i) = N.ldlt().solve(B.row(i).transpose()).transpose();
  }
  return X;
}

// Leading singular pair of the weighted residual sqrt(a_i b_j) M_ij (Q - U V^T)_ij by power iteration,
// returned as sqrt(sigma) l and sqrt(sigma) r.
void leading_residual_term(const AlsProblem& p, const Eigen::MatrixXd& Q, const Eigen::MatrixXd& U,
                           const Eigen::MatrixXd& V, Eigen::VectorXd& u, Eigen::VectorXd& v) {
  Eigen::MatrixXd S = Q;
  if (U.cols() > 0) S.noalias() -= U * V.transpose();
  S.array() *= p.W.array().sqrt();
  Eigen::VectorXd r = Eigen::VectorXd::Ones(S.cols()), l;
  double sigma = 0.0;
  for (int it = 0; it < 300; ++it) {
    l = S * r;
    const double ln = l.norm();
    if (!(ln > 0.0)) break;
    l /= ln;
    r = S.transpose() * l;
    const double s = r.norm();
    if (!(s > 0.0)) break;
    r /= s;
    const bool done = std::abs(s - sigma) <= 1e-10 * s;
    sigma = s;
    if (done) break;
  }
  u = Eigen::VectorXd::Zero(S.rows());
  v = Eigen::VectorXd::Zero(S.cols());
  if (!(sigma > 0.0)) return;
  // Still in weighted scale: the caller divides by sqrt(a) and sqrt(b).
  u = std::sqrt(sigma) * l;
  v = std::sqrt(sigma) * r;
}

struct ChannelFit {
  Eigen::MatrixXd U, V;  // H x R, D x R
  std::vector<double> error_by_rank;
  std::vector<int> sweeps;
  bool zero = false;
};

int als_sweeps(const AlsProblem& p, const Eigen::MatrixXd& Q, Eigen::MatrixXd& U, Eigen::MatrixXd& V,
               const HalfAngleFitOptions& o, double& e2) {
  double obj = weighted_error2(p, Q, U, V).second;
  int sweep = 0;
  for (; sweep < o.max_sweeps; ++sweep) {
    U = solve_side(p.W, p.WQ, V);
    V = solve_side(p.W.transpose(), p.WQ.transpose(), U);
    const auto [err2, obj2] = weighted_error2(p, Q, U, V);
    const bool stalled = obj - obj2 <= o.sweep_tolerance * obj;
    obj = obj2;
    e2 = err2;
    if (stalled || obj <= 1e-30 * p.norm2) {
      ++sweep;
      break;
    }
  }
  return sweep;
}

// Orders the terms by weighted energy: U V^T = (U') (V')^T with diag(sqrt a) U' and diag(sqrt b) V'
// orthogonal columns scaled by sqrt(sigma); returns sigma.
Eigen::VectorXd orthogonalize(Eigen::MatrixXd& U, Eigen::MatrixXd& V, const Eigen::VectorXd& a,
                              const Eigen::VectorXd& b) {
  const int R = static_cast<int>(U.cols());
  if (R == 0) return {};
  const Eigen::VectorXd sa = a.array().sqrt(), sb = b.array().sqrt();
  const Eigen::MatrixXd Ua = sa.asDiagonal() * U, Vb = sb.asDiagonal() * V;
  Eigen::HouseholderQR<Eigen::MatrixXd> qu(Ua), qv(Vb);
  const Eigen::MatrixXd Q1 = qu.householderQ() * Eigen::MatrixXd::Identity(U.rows(), R);
  const Eigen::MatrixXd Q2 = qv.householderQ() * Eigen::MatrixXd::Identity(V.rows(), R);
  const Eigen::MatrixXd R1 = qu.matrixQR().topRows(R).triangularView<Eigen::Upper>();
  const Eigen::MatrixXd R2 = qv.matrixQR().topRows(R).triangularView<Eigen::Upper>();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(R1 * R2.transpose(), Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::VectorXd sig = svd.singularValues();
  const Eigen::VectorXd root = sig.array().sqrt();
  U = sa.cwiseInverse().asDiagonal() * (Q1 * svd.matrixU() * root.asDiagonal());
  V = sb.cwiseInverse().asDiagonal() * (Q2 * svd.matrixV() * root.asDiagonal());
  return sig;
}

}  // namespace

// Eigen's products on one thread for the lifetime of the guard (restored after). The fit's products are
// small (nodes x R): threading them gained nothing on an idle 2-core machine and cost 25x on a loaded one
// (measured: GGX 0.2, 64 x 2048 nodes, rank 3: 0.21 s on one thread, 5.6 s on two beside other work).
// Eigen's thread count is one setting for the process, and fits run on several threads at once in a bank
// build (icobrdf/pipeline/bank_builder.hpp): the first guard in sets it, the last one out restores it.
class SerialEigen {
 public:
  SerialEigen() {
    std::lock_guard<std::mutex> g(state().lock);
    if (state().holders++ == 0) {
      // A count equal to this thread's OpenMP one is taken as Eigen's default (follow OpenMP, -1): restoring
      // a pinned count would pin a worker's 1 thread on the whole process after its fit.
      const int n = Eigen::nbThreads();
      state().previous = n == omp_get_max_threads() ? -1 : n;
      Eigen::setNbThreads(1);
    }
  }
  ~SerialEigen() {
    std::lock_guard<std::mutex> g(state().lock);
    if (--state().holders == 0) Eigen::setNbThreads(state().previous);
  }
  SerialEigen(const SerialEigen&) = delete;
  SerialEigen& operator=(const SerialEigen&) = delete;

 private:
  struct State {
    std::mutex lock;
    int holders = 0, previous = 0;
  };
  static State& state() {
    static State s;
    return s;
  }
};

namespace {

void check_fit_options(int channels, const HalfAngleFitOptions& o) {
  const auto bad = [](const std::string& what) { throw ArgumentError("half-angle fit: " + what); };
  if (channels < 1) bad("channels = " + std::to_string(channels) + ", expected >= 1");
  if (o.n_t < 2 || o.n_theta_d < 2 || o.n_phi_d < 1 || (!o.isotropic && o.n_phi_h < 1))
    bad("grid sizes n_t = " + std::to_string(o.n_t) + ", n_phi_h = " + std::to_string(o.n_phi_h) +
        ", n_theta_d = " + std::to_string(o.n_theta_d) + ", n_phi_d = " + std::to_string(o.n_phi_d) +
        ", expected n_t, n_theta_d >= 2 and n_phi_h, n_phi_d >= 1");
  if (!(o.h_warp >= 0.25 && o.h_warp <= 8.0)) bad("h_warp outside [0.25, 8]");
  if (!o.isotropic && !(std::abs(o.h_axis) <= M_PI && o.h_scale_1 >= kMinHScale && o.h_scale_1 <= kMaxHScale &&
                        o.h_scale_2 >= kMinHScale && o.h_scale_2 <= kMaxHScale))
    bad("h stretch outside h_axis in [-pi, pi], scales in [" + std::to_string(kMinHScale) + ", " + std::to_string(kMaxHScale) + "]");
  if (!(o.target > 0.0)) bad("target must be > 0");
  if (o.max_rank < 1 || o.fixed_rank < 0 || o.max_rank > kMaxFitRank || o.fixed_rank > kMaxFitRank)
    bad("max_rank must be in [1, " + std::to_string(kMaxFitRank) + "] and fixed_rank in [0, " + std::to_string(kMaxFitRank) + "]");
}

// The node values q, the fitting weights W (valid nodes, and the extension at a small weight) and the error
// weights Wv (valid nodes only) of a fit.
struct SampledNodes {
  std::vector<Eigen::MatrixXd> Q;  // per channel, H x D
  Eigen::MatrixXd W, Wv;           // H x D
  long long missing = 0;           // valid node pairs left out as missing data
};

// Samples q at the valid node pairs (weight a_h b_d), then at the missing nodes that share an interpolation
// cell with a valid one (weight extension_weight a_h b_d, extended values).
SampledNodes sample_nodes(const PairSampler& sampler, int channels, const HalfAngleFitOptions& o, const HalfAngleFactors& F,
                          const Eigen::VectorXd& a, const Eigen::VectorXd& b, double* valid_fraction) {
  const int H = F.h_nodes(), D = F.d_nodes();
  SampledNodes out{std::vector<Eigen::MatrixXd>(channels, Eigen::MatrixXd::Zero(H, D)), Eigen::MatrixXd::Zero(H, D),
                   Eigen::MatrixXd::Zero(H, D)};
  std::vector<Eigen::MatrixXd>& Q = out.Q;
  Eigen::MatrixXd &W = out.W, &Wv = out.Wv;
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> valid(H, D);
  const HalfAngleNodeTrig ht = half_angle_h_trig(F), dt = half_angle_d_trig(F);
  for (int i = 0; i < H; ++i)
    for (int j = 0; j < D; ++j) valid(i, j) = node_pair_valid(ht, i, dt, j);
  *valid_fraction = valid.cast<double>().mean();
  const auto near_valid = [&](int i, int j) {
    const int k = i / F.n_phi_h, jh = i % F.n_phi_h, ad = j / F.n_phi_d, bd = j % F.n_phi_d;
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = (F.n_phi_h > 1 ? -1 : 0); dj <= (F.n_phi_h > 1 ? 1 : 0); ++dj)
        for (int da = -1; da <= 1; ++da)
          for (int db = (F.n_phi_d > 1 ? -1 : 0); db <= (F.n_phi_d > 1 ? 1 : 0); ++db) {
            const int k2 = k + dk, a2 = ad + da;
            if (k2 < 0 || k2 >= F.n_t || a2 < 0 || a2 >= F.n_theta_d) continue;
            const int j2 = (jh + dj + F.n_phi_h) % F.n_phi_h, b2 = (bd + db + F.n_phi_d) % F.n_phi_d;
            if (valid(k2 * F.n_phi_h + j2, a2 * F.n_phi_d + b2)) return true;
          }
    return false;
  };
  // Extension across the horizon: f at the directions pushed onto the horizon (z -> 0, renormalized),
  // times the signed cosines for the cosine quantity; q is then C^1 across the boundary where f is
  // continuous, so that interpolation cells straddling it stay second-order accurate.
  const auto to_horizon = [](Eigen::Vector3d& w) {
    if (w.z() >= 0.0) return true;
    const double r = std::hypot(w.x(), w.y());
    if (!(r > 1e-3)) return false;
    w = Eigen::Vector3d(w.x() / r, w.y() / r, 0.0);
    return true;
  };
  const bool extend = o.extension_weight > 0.0;
  const int block = std::max(1, (1 << 16) / D);
  for (int h0 = 0; h0 < H; h0 += block) {
    const int h1 = std::min(H, h0 + block);
    std::vector<std::pair<int, int>> nodes;
    std::vector<double> cosines, metric_factor;
    RowMatrix3d wi((h1 - h0) * D, 3), wr((h1 - h0) * D, 3);
    for (int i = h0; i < h1; ++i)
      for (int j = 0; j < D; ++j) {
        if (!valid(i, j) && !(extend && near_valid(i, j))) continue;
        Eigen::Vector3d x, y;
        half_angle_node_pair(F, i, j, x, y);
        const double cc = o.quantity == HalfAngleQuantity::MeanCosine ? 0.5 * (x.z() + y.z()) : x.z() * y.z();
        if (valid(i, j)) {
          x.z() = std::max(x.z(), 0.0);
          y.z() = std::max(y.z(), 0.0);
        } else if (!to_horizon(x) || !to_horizon(y)) {
          continue;
        }
        wi.row(nodes.size()) = x.transpose();
        wr.row(nodes.size()) = y.transpose();
        nodes.emplace_back(i, j);
        const double ci = std::max(x.z(), 0.0), cr = std::max(y.z(), 0.0);
        cosines.push_back(!valid(i, j) ? cc : o.quantity == HalfAngleQuantity::MeanCosine ? 0.5 * (ci + cr) : ci * cr);
        // Mean-cosine: the metric's q = f ci cr is the stored p times H = 2 ci cr / (ci + cr).
        metric_factor.push_back(o.quantity != HalfAngleQuantity::MeanCosine || !valid(i, j) ? 1.0
                                : ci + cr > 0.0                                             ? 2.0 * ci * cr / (ci + cr)
                                                                                            : 0.0);
      }
    const auto n = static_cast<Eigen::Index>(nodes.size());
    if (n == 0) continue;
    const RowMatrix3d wiv = wi.topRows(n), wrv = wr.topRows(n);
    Eigen::MatrixXd f(n, channels);
    sampler(wiv, wrv, f);
    for (Eigen::Index k = 0; k < n; ++k) {
      const auto [i, j] = nodes[k];
      const double cc = o.quantity != HalfAngleQuantity::F ? cosines[k] : 1.0;
      if (o.skip_missing && !(f.row(k).array() * cc).allFinite()) {  // missing data: a gap, like the horizon
        out.missing += valid(i, j) ? 1 : 0;
        continue;
      }
      for (int c = 0; c < channels; ++c) {
        const double q = f(k, c) * cc;
        if (!std::isfinite(q)) {
          std::ostringstream s;
          s << "the sampled f of channel " << c << " is not finite (" << f(k, c) << ") at w_i = (" << wiv.row(k)
            << "), w_r = (" << wrv.row(k) << ")";
          throw ArgumentError("half-angle fit: " + s.str());
        }
        Q[c](i, j) = q;
      }
      const double m2 = metric_factor[k] * metric_factor[k];
      W(i, j) = a(i) * b(j) * (valid(i, j) ? m2 : o.extension_weight);
      if (valid(i, j)) Wv(i, j) = a(i) * b(j) * m2;
    }
  }

  return out;
}

// Rank by rank, every channel that still misses the target gets one more term; returns the rank reached.
int grow_ranks(const SampledNodes& n, const HalfAngleFitOptions& o, const Eigen::VectorXd& a, const Eigen::VectorXd& b,
               std::vector<ChannelFit>& cf, std::vector<double>& norm2, std::vector<double>& e2, std::vector<int>& sweeps_by_rank) {
  const int channels = static_cast<int>(n.Q.size());
  const Eigen::Index H = n.W.rows(), D = n.W.cols();
  const std::vector<Eigen::MatrixXd>& Q = n.Q;
  const Eigen::MatrixXd &W = n.W, &Wv = n.Wv;
  const int max_rank = o.fixed_rank > 0 ? o.fixed_rank : o.max_rank;
  const double target2 = o.fixed_rank > 0 ? -1.0 : o.target * o.target;
  cf.assign(channels, ChannelFit{});
  std::vector<Eigen::MatrixXd> WQ(channels);
  norm2.assign(channels, 0.0);
  e2.assign(channels, 0.0);
  for (int c = 0; c < channels; ++c) {
    WQ[c] = W.cwiseProduct(Q[c]);
    norm2[c] = Wv.cwiseProduct(Q[c]).cwiseProduct(Q[c]).sum();
    cf[c].U.resize(H, 0);
    cf[c].V.resize(D, 0);
    cf[c].zero = !(norm2[c] > 0.0);
    e2[c] = cf[c].zero ? 0.0 : norm2[c];
  }
  const Eigen::VectorXd sa = a.array().sqrt(), sb = b.array().sqrt();
  int rank = 0;
  for (int r = 1; r <= max_rank; ++r) {
    bool any = false;
    int sweeps = 0;
    for (int c = 0; c < channels; ++c) {
      if (cf[c].zero || e2[c] <= target2 * norm2[c]) continue;
      any = true;
      const AlsProblem p{W, WQ[c], Wv, norm2[c]};
      Eigen::VectorXd un, vn;
      leading_residual_term(p, Q[c], cf[c].U, cf[c].V, un, vn);
      // The residual was scaled by sqrt(W) = sqrt(a_i b_j) on valid nodes: unscale the singular vectors.
      un = un.cwiseQuotient(sa);
      vn = vn.cwiseQuotient(sb);
      Eigen::MatrixXd U(H, r), V(D, r);
      U << cf[c].U, un;
      V << cf[c].V, vn;
      const int s = als_sweeps(p, Q[c], U, V, o, e2[c]);
      sweeps = std::max(sweeps, s);
      cf[c].U = std::move(U);
      cf[c].V = std::move(V);
      cf[c].error_by_rank.push_back(std::sqrt(e2[c] / norm2[c]));
    }
    if (!any) break;
    rank = r;
    sweeps_by_rank.push_back(sweeps);
  }

  return rank;
}

}  // namespace

HalfAngleFit fit_half_angle(const PairSampler& sampler, int channels, const HalfAngleFitOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const SerialEigen serial;
  check_fit_options(channels, o);
  HalfAngleFit fit;
  HalfAngleFactors& F = fit.factors;
  F.quantity = o.quantity;
  F.corners = o.corners;
  F.centred = o.centred;
  F.isotropic = o.isotropic;
  F.h_warp = o.h_warp;
  if (!o.isotropic) F.h_axis = o.h_axis, F.h_scale_1 = o.h_scale_1, F.h_scale_2 = o.h_scale_2;
  F.n_t = o.n_t;
  F.n_phi_h = o.isotropic ? 1 : o.n_phi_h;
  F.n_theta_d = o.n_theta_d;
  F.n_phi_d = o.n_phi_d;
  const int H = F.h_nodes(), D = F.d_nodes();
  const Eigen::VectorXd a = half_angle_h_weights(F), b = half_angle_d_weights(F);
  const SampledNodes nodes = sample_nodes(sampler, channels, o, F, a, b, &fit.report.valid_fraction);
  fit.report.missing_nodes = nodes.missing;
  std::vector<ChannelFit> cf;
  std::vector<double> norm2, e2;
  const int rank = grow_ranks(nodes, o, a, b, cf, norm2, e2, fit.report.sweeps_by_rank);

  F.rank = rank;
  fit.report.rank = rank;
  fit.report.error.resize(channels);
  fit.report.error_by_rank.resize(channels);
  fit.report.energies.resize(channels);
  double worst = 0.0;
  for (int c = 0; c < channels; ++c) {
    Eigen::MatrixXd U = Eigen::MatrixXd::Zero(H, rank), V = Eigen::MatrixXd::Zero(D, rank);
    U.leftCols(cf[c].U.cols()) = cf[c].U;
    V.leftCols(cf[c].V.cols()) = cf[c].V;
    const Eigen::VectorXd sig = orthogonalize(U, V, a, b);
    const double e = cf[c].zero ? 0.0 : std::sqrt(e2[c] / norm2[c]);
    fit.report.error[c] = e;
    fit.report.error_by_rank[c] = cf[c].error_by_rank;
    for (int k = 0; k < sig.size(); ++k)
      fit.report.energies[c].push_back(cf[c].zero ? 0.0 : sig(k) / std::sqrt(norm2[c]));
    worst = std::max(worst, e);
    F.u.emplace_back(U);
    F.v.emplace_back(V);
  }
  fit.report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (o.fixed_rank == 0 && worst > o.target) {
    std::ostringstream s;
    s << "half-angle fit: rank " << o.max_rank << " reaches a weighted relative error of " << worst
      << ", above the target " << o.target << " (grid n_t = " << F.n_t << ", n_phi_h = " << F.n_phi_h
      << ", n_theta_d = " << F.n_theta_d << ", n_phi_d = " << F.n_phi_d << "); raise max_rank or the target";
    throw UnsupportedError(s.str());
  }
  return fit;
}

}  // namespace icobrdf
