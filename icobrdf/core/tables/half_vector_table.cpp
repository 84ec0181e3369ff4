#include "icobrdf/core/tables/half_vector_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/fast_atan2.hpp"
#include "icobrdf/core/support/huge_pages.hpp"
#include "icobrdf/core/support/memory_budget.hpp"

namespace icobrdf {
namespace {

// Points per side of a cell the horizon of w_r cuts, where its mass and slopes are taken.
constexpr int kHorizonShareSide = 8;

// A point of a cell the horizon cuts whose w_r is above it: w_r, cos(theta_r) 4 (w_i . h), the cell
// coordinates xi, eta of h.
struct HorizonPoint {
  Eigen::Vector3d wr;
  double jac, xi, eta;
};

// w_r = 2 (w_i . h) h - w_i.
inline Eigen::Vector3d reflect_about(const Eigen::Vector3d& wi, const Eigen::Vector3d& h) { return 2.0 * wi.dot(h) * h - wi; }

inline Eigen::Vector3d polar_vector(double cos_theta, double phi) {
  const double s = std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta));
  return {s * std::cos(phi), s * std::sin(phi), cos_theta};
}

// The x in [0, 1] where the cumulative of the density 1 + a (x - 1/2) (a in [-2, 2]) reaches u in [0, 1]: the
// root of (a/2) x^2 + (1 - a/2) x = u in the form free of cancellation, 2u / ((1 - a/2) + sqrt((1 - a/2)^2 + 2 a u)).
inline double linear_density_inverse(double a, double u) {
  const double p = 1.0 - 0.5 * a, den = p + std::sqrt(std::max(0.0, p * p + 2.0 * a * u));
  return den > 0.0 ? std::clamp(2.0 * u / den, 0.0, 1.0) : 0.0;
}

// One slope unit (a multiplication: a division by kHalfVectorSlopeUnit has 10 times its cost; the product
// differs from the quotient by at most an ulp).
constexpr double kSlopePerUnit = 1.0 / kHalfVectorSlopeUnit;

// cos and sin of an angle x in [0, 0.05] by their Taylor series to the 10th and 11th power (the first terms
// left out are below 0.05^12 / 12! < 1e-24), in Horner form on x^2 with the coefficients 1 / n! (no division).
inline void small_angle_cos_sin(double x, double& c, double& s) {
  constexpr double f2 = 1.0 / 2, f4 = f2 / 12, f6 = f4 / 30, f8 = f6 / 56, f10 = f8 / 90;
  constexpr double f3 = 1.0 / 6, f5 = f3 / 20, f7 = f5 / 42, f9 = f7 / 72, f11 = f9 / 110;
  const double x2 = x * x;
  c = 1.0 - x2 * (f2 - x2 * (f4 - x2 * (f6 - x2 * (f8 - x2 * f10))));
  s = x * (1.0 - x2 * (f3 - x2 * (f5 - x2 * (f7 - x2 * (f9 - x2 * f11)))));
}

// A slope within a cell, clamped to +-kHalfVectorMaxSlope, in units of 1 / kHalfVectorSlopeUnit.
inline std::int16_t slope_units(double x) {
  return static_cast<std::int16_t>(std::lround(std::clamp(x, -kHalfVectorMaxSlope, kHalfVectorMaxSlope) * kHalfVectorSlopeUnit));
}

[[noreturn]] void refuse_value(double x, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) {
  char buf[200];
  std::snprintf(buf, sizeof buf, "half-vector table: fbar = %.6g at w_i = (%.6g, %.6g, %.6g), w_r = (%.6g, %.6g, %.6g); expected a finite value >= 0",
                x, wi.x(), wi.y(), wi.z(), wr.x(), wr.y(), wr.z());
  throw UnsupportedError(buf);
}

// The coefficients c_n = (2n)! / (4^n (n!)^2 (2n + 1)) of asin(u) = u sum_n c_n u^(2n), n < 8, by the recurrence
// c_n = c_(n-1) (2n - 1)^2 / (2n (2n + 1)).
struct AsinSeries {
  double c[8];
};
constexpr AsinSeries make_asin_series() {
  AsinSeries a{};
  a.c[0] = 1.0;
  for (int n = 1; n < 8; ++n) a.c[n] = a.c[n - 1] * (2.0 * n - 1) * (2.0 * n - 1) / (2.0 * n * (2.0 * n + 1));
  return a;
}
constexpr AsinSeries kAsinSeries = make_asin_series();

}  // namespace

double HalfVectorTable::blend_theta(double z) {
  const double u2 = std::clamp(0.5 * (1.0 - z), 0.0, 1.0), u = std::sqrt(u2);  // u = sin(theta / 2)
  const double* c = kAsinSeries.c;
  const double p = c[0] + u2 * (c[1] + u2 * (c[2] + u2 * (c[3] + u2 * (c[4] + u2 * (c[5] + u2 * (c[6] + u2 * c[7]))))));
  return 2.0 * u * p;
}

void HalfVectorTable::check(const HalfVectorTableOptions& o) {
  const bool ok = o.theta_nodes >= 2 && (o.azimuth_nodes == 1 || o.azimuth_nodes >= 4) && o.t_bins >= 4 &&
                  o.phi_bins >= 4 && o.t_warp >= 1.0 && o.t_warp <= 4.0;
  if (!ok)
    throw ArgumentError("half-vector table: expected theta_nodes >= 2, azimuth_nodes 1 or >= 4, t_bins >= 4, phi_bins >= 4, "
                        "t_warp in [1, 4]; got " + std::to_string(o.theta_nodes) + ", " + std::to_string(o.azimuth_nodes) +
                        ", " + std::to_string(o.t_bins) + ", " + std::to_string(o.phi_bins) + ", " + std::to_string(o.t_warp));
}

Eigen::Vector3d HalfVectorTable::node_direction(const HalfVectorTableOptions& opt, int n) {
  const int a = n / opt.azimuth_nodes, b = n % opt.azimuth_nodes;
  const double theta = kHalfVectorThetaMax * a / (opt.theta_nodes - 1), phi = 2.0 * M_PI * b / opt.azimuth_nodes;
  return polar_vector(std::cos(theta), phi);
}

double HalfVectorTable::cell_area(int cell) const {
  const int k = cell / phi_cells_;
  return (cos_edge_[static_cast<size_t>(k)] - cos_edge_[static_cast<size_t>(k) + 1]) * (2.0 * M_PI / opt_.phi_bins);
}

void HalfVectorTable::lay_out_cells() {
  // Mirrored (isotropic, an even number of phi bins): the nodes' w_i lie in the xz plane, so q(h) is even in
  // phi_h and only the bins of phi_h in [0, pi) are stored.
  mirrored_ = stores_mirror_image(opt_);
  phi_cells_ = mirrored_ ? opt_.phi_bins / 2 : opt_.phi_bins;
  inv_phi_cells_ = 1.0 / phi_cells_;
  phi_lo_ = mirrored_ ? 0.0 : -M_PI;
  const int nt = opt_.t_bins, np = phi_cells_;
  cells_ = nt * np;
  cos_edge_.resize(static_cast<size_t>(nt) + 1);
  for (int k = 0; k <= nt; ++k) cos_edge_[static_cast<size_t>(k)] = std::cos(0.5 * M_PI * std::pow(static_cast<double>(k) / nt, opt_.t_warp));
  cos_edge_[static_cast<size_t>(nt)] = 0.0;
  density_scale_.resize(static_cast<size_t>(nt));
  for (int k = 0; k < nt; ++k)  // mirrored: a cell and its image share the cell's mass
    density_scale_[static_cast<size_t>(k)] = (mirrored_ ? 0.5 : 1.0) / cell_area(k * phi_cells_);
  const double dphi = 2.0 * M_PI / opt_.phi_bins;
  phi_edge_cs_.resize(2 * static_cast<size_t>(np));
  for (int j = 0; j < np; ++j) {
    phi_edge_cs_[2 * static_cast<size_t>(j)] = std::cos(phi_lo_ + dphi * j);
    phi_edge_cs_[2 * static_cast<size_t>(j) + 1] = std::sin(phi_lo_ + dphi * j);
  }
  // Slot i starts at u = i / L, cos theta_h = 1 - u^4 (its largest cos): the first bin whose lower edge is at
  // or below it; a cos within the slot is in that bin or a later one.
  t_lookup_.resize(static_cast<size_t>(kHalfVectorTLookup) + 1);
  for (int i = 0, k = 0; i <= kHalfVectorTLookup; ++i) {
    const double u = static_cast<double>(i) / kHalfVectorTLookup, cz = 1.0 - u * u * u * u;
    while (k + 1 < nt && cz < cos_edge_[static_cast<size_t>(k) + 1]) ++k;
    t_lookup_[static_cast<size_t>(i)] = k;
  }
}

double HalfVectorTable::bytes(const HalfVectorTableOptions& o) {
  check(o);
  const double cells = static_cast<double>(o.t_bins) * (stores_mirror_image(o) ? o.phi_bins / 2 : o.phi_bins);
  const double nodes = static_cast<double>(o.theta_nodes) * o.azimuth_nodes;
  // Per stored cell while a node is built: 4 sub-cell rows of h, w_i and w_r (3 doubles each), their
  // Jacobians and values, the node's masses and flags.
  constexpr double kWorkBytesPerCell = 4 * 3 * 3 * 8 + 4 * 8 * 2 + 8 + 1;
  return nodes * cells * static_cast<double>(sizeof(CellEntry) + sizeof(AliasEntry)) + cells * kWorkBytesPerCell;
}

HalfVectorTable::HalfVectorTable(const NonNegativeBrdf& fbar, const HalfVectorTableOptions& options) : opt_(options) {
  check(opt_);
  require_memory(bytes(opt_),
                 "half-vector tables of " + std::to_string(nodes()) + " incident nodes x " + std::to_string(opt_.t_bins) + " x " +
                     std::to_string(opt_.phi_bins) + " half-vector bins",
                 "fewer t_bins, phi_bins, theta_nodes or azimuth_nodes fit");
  lay_out_cells();
  const int nt = opt_.t_bins, np = phi_cells_;
  const int n_nodes = nodes();
  const auto total = static_cast<size_t>(n_nodes) * static_cast<size_t>(cells_);
  // Read at random cells per draw: huge pages (advised before the first write) spare the TLB misses' page walks.
  cells_of_nodes_.reserve(total), alias_.reserve(total);
  advise_huge_pages(cells_of_nodes_.data(), total * sizeof(CellEntry));
  advise_huge_pages(alias_.data(), total * sizeof(AliasEntry));
  cells_of_nodes_.assign(total, CellEntry{0.0f, 0, 0});
  alias_.assign(total, AliasEntry{1.0f, 0, 0, 0});
  albedo_.assign(static_cast<size_t>(n_nodes), 0.0);
  const double dphi = 2.0 * M_PI / opt_.phi_bins;
  std::vector<double> node_mass(static_cast<size_t>(cells_));
  std::vector<AliasEntry> alias_row(static_cast<size_t>(cells_));  // one node's alias table, then stored cell-major
  // Sub-cell centres: 2 x 2 per cell, equal in solid angle (midpoints in cos theta_h and phi_h).
  RowMatrix3d h(static_cast<Eigen::Index>(cells_) * 4, 3);
  for (int k = 0; k < nt; ++k)
    for (int j = 0; j < np; ++j)
      for (int q = 0; q < 4; ++q) {
        const double c0 = cos_edge_[static_cast<size_t>(k)], c1 = cos_edge_[static_cast<size_t>(k) + 1];
        const double c = c0 + (c1 - c0) * (0.25 + 0.5 * (q / 2)), phi = phi_lo_ + dphi * (j + 0.25 + 0.5 * (q % 2));
        h.row((static_cast<Eigen::Index>(k) * np + j) * 4 + q) = polar_vector(c, phi).transpose();
      }
  RowMatrix3d wi(h.rows(), 3), wr(h.rows(), 3);
  for (int n = 0; n < n_nodes; ++n) {
    const Eigen::Vector3d w = node_direction(n);
    wi.rowwise() = w.transpose();
    Eigen::VectorXd jac(h.rows());  // cos(theta_r) 4 (w_i . h), 0 where w_r cannot be
    for (Eigen::Index r = 0; r < h.rows(); ++r) {
      const Eigen::Vector3d hr = h.row(r).transpose();
      const double c = w.dot(hr);
      const Eigen::Vector3d o = reflect_about(w, hr);
      jac[r] = (c > 0.0 && o.z() >= 0.0) ? o.z() * 4.0 * c : 0.0;
      wr.row(r) = jac[r] > 0.0 ? o.transpose() : Eigen::RowVector3d(0, 0, 1);  // fbar is not asked below the horizon
    }
    const Eigen::VectorXd v = fbar(wi, wr);
    double* m = node_mass.data();
    std::fill(node_mass.begin(), node_mass.end(), 0.0);
    double sum = 0.0;
    int open = 0;  // cells that can hold reflected directions
    std::vector<char> can(static_cast<size_t>(cells_), 0);
    std::vector<int> cut;  // cells the horizon of w_r cuts
    for (int cell = 0; cell < cells_; ++cell) {
      double s = 0.0, sub[4] = {0, 0, 0, 0};
      bool any = false;
      int valid = 0;
      for (int q = 0; q < 4; ++q) {
        const Eigen::Index r = static_cast<Eigen::Index>(cell) * 4 + q;
        if (jac[r] == 0.0) continue;
        any = true;
        ++valid;
        const double x = v[r];
        if (!(x >= 0.0) || !std::isfinite(x)) refuse_value(x, w, wr.row(r).transpose());
        s += sub[q] = x * jac[r];
      }
      // Slopes of the linear fit through the sub-cell values (xi = 1/4, 3/4 at q / 2 = 0, 1; eta at q % 2):
      // the difference of the halves' means is mean x slope / 2.
      CellEntry& e = cells_of_nodes_[static_cast<size_t>(cell) * static_cast<size_t>(n_nodes) + static_cast<size_t>(n)];
      if (s > 0.0) {
        const double mean = s / 4;
        e.a = slope_units((sub[2] + sub[3] - sub[0] - sub[1]) / mean);
        e.b = slope_units((sub[1] + sub[3] - sub[0] - sub[2]) / mean);
      }
      if (!any) {  // the corners: a sliver of the cell may still reflect above the horizon
        const int k = cell / np, j = cell % np;
        for (int q = 0; q < 4 && !any; ++q) {
          const Eigen::Vector3d hc = polar_vector(cos_edge_[static_cast<size_t>(k + q / 2)], phi_lo_ + dphi * (j + q % 2));
          any = w.dot(hc) > 0.0 && reflect_about(w, hc).z() >= 0.0;
        }
      }
      m[cell] = valid == 4 ? s / 4 * cell_area(cell) : 0.0;
      // A cell the horizon cuts: its mass and slopes from the kHorizonShareSide^2 points below (its sub-cell
      // centres can all lie beyond the horizon while a sliver of it holds a share of the albedo).
      if (valid < 4 && any) cut.push_back(cell);
      if (any) can[static_cast<size_t>(cell)] = 1, ++open;
    }
    cut_cells(w, cut, fbar, m, n);
    for (int cell = 0; cell < cells_; ++cell) sum += m[cell];
    albedo_[static_cast<size_t>(n)] = mirrored_ ? 2.0 * sum : sum;  // the mirror image holds the other half
    if (!(sum > 0.0)) continue;  // an all-zero node: never drawn (its blend weight goes to no draw)
    const double floor = kHalfVectorFloor * sum / open;
    double acc = 0.0;
    for (int cell = 0; cell < cells_; ++cell) {
      if (can[static_cast<size_t>(cell)]) m[cell] = std::max(m[cell], floor);
      acc += m[cell];
    }
    // The masses as pdf() reads them (float), normalized again, are what the alias table draws.
    double rounded = 0.0;
    for (int cell = 0; cell < cells_; ++cell) rounded += static_cast<float>(m[cell] / acc);
    for (int cell = 0; cell < cells_; ++cell) {
      const float p = static_cast<float>(m[cell] / acc);
      cells_of_nodes_[static_cast<size_t>(cell) * static_cast<size_t>(n_nodes) + static_cast<size_t>(n)].mass = p;
      m[cell] = p / rounded;
    }
    build_alias(m, alias_row.data());
    for (int cell = 0; cell < cells_; ++cell) {  // the alias cell's slopes beside its index (see sample())
      AliasEntry x = alias_row[static_cast<size_t>(cell)];
      const CellEntry& e = entry(n, x.alias);
      x.a = e.a, x.b = e.b;
      alias_[static_cast<size_t>(cell) * static_cast<size_t>(n_nodes) + static_cast<size_t>(n)] = x;
    }
  }
}

void HalfVectorTable::cut_cells(const Eigen::Vector3d& wi, const std::vector<int>& cut, const NonNegativeBrdf& fbar, double* m,
                                int node) {
  constexpr int side = kHorizonShareSide;
  const double dphi = 2.0 * M_PI / opt_.phi_bins;
  std::vector<HorizonPoint> points;
  std::vector<int> first(cut.size() + 1, 0);  // the points of cut[i]: [first[i], first[i + 1])
  for (size_t i = 0; i < cut.size(); ++i) {
    const int k = cut[i] / phi_cells_, j = cut[i] % phi_cells_;
    const double c0 = cos_edge_[static_cast<size_t>(k)], c1 = cos_edge_[static_cast<size_t>(k) + 1];
    for (int a = 0; a < side; ++a)
      for (int b = 0; b < side; ++b) {
        const double xi = (a + 0.5) / side, eta = (b + 0.5) / side;
        const Eigen::Vector3d h = polar_vector(c0 + (c1 - c0) * xi, phi_lo_ + dphi * (j + eta));
        const double c = wi.dot(h);
        const Eigen::Vector3d o = reflect_about(wi, h);
        if (c > 0.0 && o.z() >= 0.0) points.push_back({o, o.z() * 4.0 * c, xi, eta});
      }
    first[i + 1] = static_cast<int>(points.size());
  }
  if (points.empty()) return;
  RowMatrix3d wi_rows(static_cast<Eigen::Index>(points.size()), 3), wr_rows(static_cast<Eigen::Index>(points.size()), 3);
  for (size_t p = 0; p < points.size(); ++p) {
    wi_rows.row(static_cast<Eigen::Index>(p)) = wi.transpose();
    wr_rows.row(static_cast<Eigen::Index>(p)) = points[p].wr.transpose();
  }
  const Eigen::VectorXd v = fbar(wi_rows, wr_rows);
  for (size_t i = 0; i < cut.size(); ++i) {
    // The mass by the midpoint rule of the cell's side x side points (0 beyond the horizon); the slopes by
    // the first moments of q: the density 1 + a (xi - 1/2) has the mean xi 1/2 + a / 12.
    double s = 0.0, sx = 0.0, se = 0.0;
    for (int p = first[i]; p < first[i + 1]; ++p) {
      const HorizonPoint& q = points[static_cast<size_t>(p)];
      const double x = v[p];
      if (!(x >= 0.0) || !std::isfinite(x)) refuse_value(x, wi, q.wr);
      s += x * q.jac, sx += x * q.jac * q.xi, se += x * q.jac * q.eta;
    }
    m[cut[i]] = s / (side * side) * cell_area(cut[i]);
    CellEntry& e = cells_of_nodes_[static_cast<size_t>(cut[i]) * static_cast<size_t>(nodes()) + static_cast<size_t>(node)];
    e.a = e.b = 0;
    if (s > 0.0) e.a = slope_units(12.0 * (sx / s - 0.5)), e.b = slope_units(12.0 * (se / s - 0.5));
  }
}

void HalfVectorTable::build_alias(const double* p, AliasEntry* out) const {
  // Vose's method: cells below the mean mass are topped up from one above it (its alias).
  std::vector<double> scaled(static_cast<size_t>(cells_));
  std::vector<int> small, large;
  for (int i = 0; i < cells_; ++i) {
    scaled[static_cast<size_t>(i)] = p[i] * cells_;
    (scaled[static_cast<size_t>(i)] < 1.0 ? small : large).push_back(i);
  }
  while (!small.empty() && !large.empty()) {
    const int l = small.back(), g = large.back();
    small.pop_back();
    out[l] = AliasEntry{static_cast<float>(scaled[static_cast<size_t>(l)]), g, 0, 0};
    double& sg = scaled[static_cast<size_t>(g)];
    sg = (sg + scaled[static_cast<size_t>(l)]) - 1.0;
    if (sg < 1.0) large.pop_back(), small.push_back(g);
  }
  // What is left is 1 to rounding; an empty cell left over keeps nothing (its alias has mass).
  for (const int g : large) out[g] = AliasEntry{1.0f, g, 0, 0};
  const int best = static_cast<int>(std::max_element(p, p + cells_) - p);
  for (const int l : small) out[l] = AliasEntry{p[l] > 0.0 ? 1.0f : 0.0f, best, 0, 0};
}

HalfVectorBlend HalfVectorTable::blend(const HalfVectorTableOptions& opt, const Eigen::Vector3d& wi) {
  HalfVectorBlend b;
  const double rho = std::sqrt(wi.x() * wi.x() + wi.y() * wi.y());
  const double theta = blend_theta(wi.z());
  double x = std::clamp(theta / kHalfVectorThetaMax, 0.0, 1.0) * (opt.theta_nodes - 1);
  const int a = std::min(static_cast<int>(x), opt.theta_nodes - 2);
  const double fa = x - a;
  if (opt.azimuth_nodes == 1) {
    if (rho > 0.0) b.c = wi.x() / rho, b.s = wi.y() / rho;
    b.count = 2;
    b.node[0] = a, b.weight[0] = 1.0 - fa;
    b.node[1] = a + 1, b.weight[1] = fa;
    return b;
  }
  const int m = opt.azimuth_nodes;
  double y = (rho > 0.0 ? fast_atan2(wi.y(), wi.x()) : 0.0) / (2.0 * M_PI) * m;
  if (y < 0.0) y += m;
  int p = static_cast<int>(y);
  double fp = y - p;
  if (p >= m) p = 0, fp = 0.0;
  const int p1 = p + 1 == m ? 0 : p + 1;
  b.count = 4;
  b.node[0] = a * m + p, b.weight[0] = (1.0 - fa) * (1.0 - fp);
  b.node[1] = a * m + p1, b.weight[1] = (1.0 - fa) * fp;
  b.node[2] = (a + 1) * m + p, b.weight[2] = fa * (1.0 - fp);
  b.node[3] = (a + 1) * m + p1, b.weight[3] = fa * fp;
  return b;
}

int HalfVectorTable::cell_of(const Eigen::Vector3d& h, double& xi, double& eta) const {
  const double z = std::clamp(h.z(), 0.0, 1.0);
  const double u = std::sqrt(std::sqrt(1.0 - z));
  int k = t_lookup_[static_cast<size_t>(std::min(static_cast<int>(u * kHalfVectorTLookup), kHalfVectorTLookup))];
  // The cell whose cos range holds h.z (the lookup's start is at or before it, one back for rounding of u).
  if (k > 0 && z > cos_edge_[static_cast<size_t>(k)]) --k;
  while (k + 1 < opt_.t_bins && z < cos_edge_[static_cast<size_t>(k) + 1]) ++k;
  const double hy = mirrored_ ? std::abs(h.y()) : h.y();  // mirrored: the image in phi_h >= 0
  const double phi = (h.x() == 0.0 && hy == 0.0) ? 0.0 : fast_atan2(hy, h.x());
  const double y = (phi - phi_lo_) / (2.0 * M_PI) * opt_.phi_bins;
  const int j = std::clamp(static_cast<int>(y), 0, phi_cells_ - 1);
  const double c0 = cos_edge_[static_cast<size_t>(k)], c1 = cos_edge_[static_cast<size_t>(k) + 1];
  xi = std::clamp((c0 - z) / (c0 - c1), 0.0, 1.0);
  eta = std::clamp(y - j, 0.0, 1.0);
  return k * phi_cells_ + j;
}

double HalfVectorTable::live_weight(const HalfVectorBlend& b) const {
  double live = 0.0;
  for (int i = 0; i < b.count; ++i)
    if (albedo_[static_cast<size_t>(b.node[i])] > 0.0) live += b.weight[i];
  return live;
}

double HalfVectorTable::albedo(const HalfVectorBlend& b) const {
  double s = 0.0;
  for (int i = 0; i < b.count; ++i) s += b.weight[i] * albedo_[static_cast<size_t>(b.node[i])];
  return s;
}

bool HalfVectorTable::sample(const HalfVectorBlend& b, const Eigen::Vector3d& wi, double u1, double u2, Eigen::Vector3d& wr,
                             double& pdf_out) const {
  // The cell index from u1 alone, so that its entries' address waits only for the blend's nodes: the alias
  // entries of the blend's nodes at that index lie side by side (cell-major) and are fetched while u2 picks
  // the node.
  double f;
  const int cell0 = cell_index(u1, f);
  const AliasEntry* row = alias_.data() + static_cast<size_t>(cell0) * static_cast<size_t>(nodes());
  for (int i = 0; i < b.count; ++i) __builtin_prefetch(row + b.node[i]), __builtin_prefetch(&entry(b.node[i], cell0));
  // The node: u2 picks it by the blend weights among the nodes that have mass, then is rescaled to [0, 1).
  double live = 0.0, x;
  int node = -1, pick = 0;  // the drawn node and its place in the blend
  if (b.count == 2) {
    const double w0 = albedo_[static_cast<size_t>(b.node[0])] > 0.0 ? b.weight[0] : 0.0;
    const double w1 = albedo_[static_cast<size_t>(b.node[1])] > 0.0 ? b.weight[1] : 0.0;
    // The reciprocals of both weights while u2 is scaled: the rescale is then a product, not a division that
    // the draw would wait for (a zero weight's infinity is never selected).
    const double r0 = 1.0 / b.weight[0], r1 = 1.0 / b.weight[1];
    live = w0 + w1;
    if (!(live > 0.0)) return false;
    x = u2 * live;
    const bool second = x >= w0 && w1 > 0.0;  // node 0 dead or of weight 0 (w0 = 0): the second
    pick = second, node = b.node[pick];
    x = std::clamp((x - (second ? w0 : 0.0)) * (second ? r1 : r0), 0.0, 1.0);
  } else {
    live = live_weight(b);
    if (!(live > 0.0)) return false;
    x = u2 * live;
    double acc = 0.0, node_lo = 0.0, node_w = 1.0;
    for (int i = 0; i < b.count; ++i) {
      if (!(albedo_[static_cast<size_t>(b.node[i])] > 0.0) || b.weight[i] == 0.0) continue;
      pick = i, node = b.node[i], node_lo = acc, node_w = b.weight[i];  // the last live node takes u2 rounding up to its end
      if (x < acc + b.weight[i]) break;
      acc += b.weight[i];
    }
    x = std::clamp((x - node_lo) / node_w, 0.0, 1.0);
  }
  u2 = x;
  // The cell from the node's alias table, the fraction left of u1 for the position within it. The alias
  // entry and the cell's own entries are read at once (both addresses follow from u1 and the node; the alias
  // entry carries its alias cell's slopes of this node), so the draw waits for one memory access, not two
  // in turn; the entries of the drawn cell, which only the density reads, are fetched meanwhile.
  const AliasEntry& a = row[node];
  const CellEntry& own = entry(node, cell0);
  const double keep = a.keep;
  // A branch, not selects, although u1 decides it: the predicted side runs on before the alias entry
  // arrives (a kept draw needs nothing of it), where selects would wait for it (measured 20 ns slower).
  const bool kept = f < keep || keep >= 1.0;
  const int cell = kept ? cell0 : a.alias;
  const CellEntry* e[4];  // the drawn cell's entries of the blend nodes
  for (int i = 0; i < b.count; ++i) __builtin_prefetch(e[i] = &entry(b.node[i], cell));  // what h_density reads
  // The drawn node's slopes as the draw read them (aliased: from the alias entry); its density uses the same.
  const CellEntry drawn{e[pick]->mass, kept ? own.a : a.a, kept ? own.b : a.b};
  e[pick] = &drawn;
  const std::int16_t sa = drawn.a, sb = drawn.b;
  f = std::clamp((kept ? f : f - keep) / (kept ? keep : 1.0 - keep), 0.0, 1.0);
  const double xi = linear_density_inverse(sa * kSlopePerUnit, f);
  // Mirrored: u2's upper half draws the image (phi_h -> -phi_h) and is rescaled to [0, 1).
  const bool image = mirrored_ && u2 >= 0.5;
  if (mirrored_) u2 = std::min(image ? 2.0 * u2 - 1.0 : 2.0 * u2, 1.0);
  const double eta = linear_density_inverse(sb * kSlopePerUnit, u2);
  // k = cell / phi_cells_ by a product (an integer division would hold up the draw for 25 cycles): the
  // quotient (cell + 1/2) / phi_cells_ is at least 1 / (2 phi_cells_) from an integer, far above the rounding.
  const int k = static_cast<int>((cell + 0.5) * inv_phi_cells_), j = cell - k * phi_cells_;
  const double c0 = cos_edge_[static_cast<size_t>(k)], c1 = cos_edge_[static_cast<size_t>(k) + 1];
  const double cz = c0 + (c1 - c0) * xi, sz = std::sqrt(std::max(0.0, 1.0 - cz * cz));
  // phi_h = lower edge + angle, angle = eta (2 pi / phi_bins) <= 0.05.
  double ca, sn;
  small_angle_cos_sin(2.0 * M_PI / opt_.phi_bins * eta, ca, sn);
  const double pc = phi_edge_cs_[2 * static_cast<size_t>(j)], ps = phi_edge_cs_[2 * static_cast<size_t>(j) + 1];
  const double hx = sz * (pc * ca - ps * sn), hy = (image ? -sz : sz) * (ps * ca + pc * sn);
  const Eigen::Vector3d h(b.c * hx - b.s * hy, b.s * hx + b.c * hy, cz);
  const double c = wi.dot(h);
  if (!(c > 0.0)) return false;
  wr = 2.0 * c * h - wi;
  if (!(wr.z() >= 0.0)) return false;
  // The density of the draw at its own cell and position (pdf() finds the same from (w_i, w_r) to rounding).
  pdf_out = h_density(b, e, k, xi, eta) / (live * 4.0 * c);
  return pdf_out > 0.0;
}

void HalfVectorTable::prefetch_draw(double u1) const {
  if (cells_ == 0 || nodes() * sizeof(AliasEntry) > kPrefetchLines * 64) return;
  double f;
  const char* row = reinterpret_cast<const char*>(alias_.data() + static_cast<size_t>(cell_index(u1, f)) * static_cast<size_t>(nodes()));
  const char* end = row + static_cast<size_t>(nodes()) * sizeof(AliasEntry);
  for (const char* p = row; p < end; p += 64) __builtin_prefetch(p);
  __builtin_prefetch(end - 1);
}

double HalfVectorTable::h_density(const HalfVectorBlend& b, const CellEntry* const* e, int k, double xi, double eta) const {
  double density = 0.0;
  const double dx = (xi - 0.5) * kSlopePerUnit, de = (eta - 0.5) * kSlopePerUnit;
  for (int i = 0; i < b.count; ++i) density += b.weight[i] * e[i]->mass * (1.0 + e[i]->a * dx) * (1.0 + e[i]->b * de);
  return density * density_scale_[static_cast<size_t>(k)];
}

double HalfVectorTable::pdf(const HalfVectorBlend& b, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  Eigen::Vector3d h;
  double c;
  if (!(wr.z() >= 0.0) || !(wi.z() >= 0.0) || !reflection_half_vector(wi, wr, h, c)) return 0.0;
  const double live = live_weight(b);
  if (!(live > 0.0)) return 0.0;
  const Eigen::Vector3d hl(b.c * h.x() + b.s * h.y(), -b.s * h.x() + b.c * h.y(), h.z());
  double xi, eta;
  const int cell = cell_of(hl, xi, eta);
  const CellEntry* e[4];
  for (int i = 0; i < b.count; ++i) e[i] = &entry(b.node[i], cell);
  return h_density(b, e, cell / phi_cells_, xi, eta) / (live * 4.0 * c);
}

}  // namespace icobrdf
