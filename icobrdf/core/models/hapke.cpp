#include "icobrdf/core/models/hapke.hpp"

#include "icobrdf/core/grid/gauss_legendre.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace icobrdf {

namespace {

constexpr int kPanelNodes = 16;      // Gauss-Legendre nodes per panel
constexpr int kDecades = 12;         // panels [0, 1e-12], [1e-12, 1e-11], ..., [0.1, 1]
constexpr int kTableIntervals = 4096;  // table uniform in t = sqrt(mu)
// Newton on the H-function nodes stops when the step is below this relative to max|H|: a few ulps of H
// (about 1), where the iteration has converged to rounding.
constexpr double kNewtonRelStep = 1e-15;

}  // namespace

ChandrasekharH::ChandrasekharH(double w) : w_(w), s_(std::sqrt(std::max(0.0, 1.0 - w))) {
  const QuadratureRule gl = gauss_legendre(kPanelNodes);
  const Eigen::VectorXd& gx = gl.nodes;
  const Eigen::VectorXd& gw = gl.weights;
  std::vector<double> edges = {0.0};
  for (int d = kDecades; d >= 1; --d) edges.push_back(std::pow(10.0, -d));
  edges.push_back(1.0);
  for (std::size_t p = 0; p + 1 < edges.size(); ++p) {
    const double a = edges[p], b = edges[p + 1];
    for (int k = 0; k < kPanelNodes; ++k) {
      nodes_.push_back(0.5 * (a + b) + 0.5 * (b - a) * gx[k]);
      weights_.push_back(0.5 * (b - a) * gw[k]);
    }
  }
  const int n = static_cast<int>(nodes_.size());
  // K_ij = c_j mu_j / (mu_i + mu_j); residual R_i = H_i (s + w/2 sum_j K_ij H_j) - 1.
  Eigen::MatrixXd k(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) k(i, j) = weights_[j] * nodes_[j] / (nodes_[i] + nodes_[j]);
  Eigen::VectorXd h = Eigen::VectorXd::Ones(n);
  for (int it = 0; it < 30; ++it) h = (s_ + 0.5 * w_ * (k * h).array()).inverse().matrix();
  for (int it = 0; it < 50; ++it) {  // Newton
    const Eigen::VectorXd q = (s_ + 0.5 * w_ * (k * h).array()).matrix();
    const Eigen::VectorXd r = (h.array() * q.array() - 1.0).matrix();
    Eigen::MatrixXd jac = 0.5 * w_ * (h.asDiagonal() * k);
    jac.diagonal() += q;
    const Eigen::VectorXd dh = jac.partialPivLu().solve(r);
    h -= dh;
    if (dh.cwiseAbs().maxCoeff() < kNewtonRelStep * h.cwiseAbs().maxCoeff()) break;
  }
  h_nodes_.assign(h.data(), h.data() + n);
  table_.resize(kTableIntervals + 1);
  for (int i = 0; i <= kTableIntervals; ++i) {
    const double t = static_cast<double>(i) / kTableIntervals;
    table_[i] = exact(t * t);
  }
}

double ChandrasekharH::exact(double mu) const {
  mu = std::clamp(mu, 0.0, 1.0);
  double sum = 0.0;
  for (std::size_t j = 0; j < nodes_.size(); ++j) sum += weights_[j] * nodes_[j] * h_nodes_[j] / (mu + nodes_[j]);
  return 1.0 / (s_ + 0.5 * w_ * sum);
}

double ChandrasekharH::operator()(double mu) const {
  const double t = std::sqrt(std::clamp(mu, 0.0, 1.0)) * kTableIntervals;
  int i = static_cast<int>(t) - 1;  // first of the 4 stencil points
  i = std::clamp(i, 0, kTableIntervals - 3);
  const double x = t - i;  // position in stencil coordinates 0..3
  const double l0 = -(x - 1) * (x - 2) * (x - 3) / 6.0, l1 = x * (x - 2) * (x - 3) / 2.0;
  const double l2 = -x * (x - 1) * (x - 3) / 2.0, l3 = x * (x - 1) * (x - 2) / 6.0;
  return l0 * table_[i] + l1 * table_[i + 1] + l2 * table_[i + 2] + l3 * table_[i + 3];
}

double LommelSeeligerModel::value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  return w_ / (4.0 * M_PI * std::max(wi.z() + wr.z(), kGrazingCosFloor));
}

std::string LommelSeeligerModel::spec() const { return format_model_spec("lommel-seeliger", {{"w", format_parameter(w_)}}); }

namespace hapke_roughness {

// Hapke's roughness functions of one direction at polar angle x (cosine c, sine s), tb = tan(theta-bar) > 0.
struct RoughAngle {
  double c, s, e1, e2, eta;
};
RoughAngle rough_angle(double c, double s, double tb, double chi) {
  RoughAngle a{c, s, 0.0, 0.0, 0.0};
  if (s > 0.0) {  // E1, E2 -> 0 at the normal (cot x -> infinity)
    const double k = c / (s * tb);  // cot(x) cot(tb)
    a.e1 = std::exp(-2.0 * k / M_PI);
    a.e2 = std::exp(-k * k / M_PI);
  }
  a.eta = chi * (c + s * tb * a.e2 / (2.0 - a.e1));
  return a;
}

}  // namespace hapke_roughness
using hapke_roughness::rough_angle;
using hapke_roughness::RoughAngle;

double HapkeModel::value(const Eigen::Vector3d& first, const Eigen::Vector3d& second) const {
  // Canonical order (z, x, y lexicographic): the formula is symmetric, and this makes its rounding symmetric too.
  const bool keep = std::make_tuple(first.z(), first.x(), first.y()) <= std::make_tuple(second.z(), second.x(), second.y());
  const Eigen::Vector3d& wi = keep ? first : second;
  const Eigen::Vector3d& wr = keep ? second : first;
  const double mi = std::clamp(wi.z(), 0.0, 1.0), mr = std::clamp(wr.z(), 0.0, 1.0);
  const double cos_g = std::clamp(wi.dot(wr), -1.0, 1.0);
  // tan(g/2) = sqrt((1 - cos g)/(1 + cos g)); B -> 0 as g -> pi.
  const double surge = b0_ > 0.0 && cos_g > -1.0 ? b0_ / (1.0 + std::sqrt((1.0 - cos_g) / (1.0 + cos_g)) / width_) : 0.0;
  if (theta_bar_ == 0.0)
    return w_ / (4.0 * M_PI) * (surge + h_(mi) * h_(mr)) / std::max(mi + mr, kGrazingCosFloor);
  const double tb = std::tan(theta_bar_ * M_PI / 180.0), chi = 1.0 / std::sqrt(1.0 + M_PI * tb * tb);
  const double si = std::hypot(wi.x(), wi.y()), sr = std::hypot(wr.x(), wr.y());
  // psi in [0, pi]: 0 when the horizontal parts point the same way (arbitrary at the normal, where it drops out).
  const double cos_psi = si > 0.0 && sr > 0.0 ? std::clamp((wi.x() * wr.x() + wi.y() * wr.y()) / (si * sr), -1.0, 1.0) : 1.0;
  const double psi = std::acos(cos_psi), sin2_half = 0.5 * (1.0 - cos_psi);
  const double fpsi = psi < M_PI ? std::exp(-2.0 * std::tan(0.5 * psi)) : 0.0;
  const RoughAngle a = rough_angle(mi, si, tb, chi), b = rough_angle(mr, sr, tb, chi);
  // Near is the direction nearer the normal (i <= e in Hapke's first branch), far the other.
  const bool a_near = mi >= mr;
  const RoughAngle& near = a_near ? a : b;
  const RoughAngle& far = a_near ? b : a;
  // 0 only with both directions on the horizon and opposite (psi = pi), where the numerators vanish too: floored.
  const double den = std::max(2.0 - far.e1 - psi / M_PI * near.e1, kGrazingCosFloor);
  const double mu_near = chi * (near.c + near.s * tb * (cos_psi * far.e2 + sin2_half * near.e2) / den);
  const double mu_far = chi * (far.c + far.s * tb * (far.e2 - sin2_half * near.e2) / den);
  // f = r / mu_i diverges as 1/mu at retro grazing (both on the horizon, psi = 0: this denominator -> 0): floored.
  const double shadow = chi / std::max(1.0 - fpsi + fpsi * chi * near.c / near.eta, kGrazingCosFloor);
  const double multiple = h_(mu_near) * h_(mu_far);
  return w_ / (4.0 * M_PI) * (mu_near * mu_far) / std::max(mu_near + mu_far, kGrazingCosFloor) * (surge + multiple) * shadow /
         (a.eta * b.eta);
}

std::string HapkeModel::spec() const {
  return format_model_spec("hapke", {{"w", format_parameter(w_)},
                                     {"b0", format_parameter(b0_)},
                                     {"h", format_parameter(width_)},
                                     {"theta", format_parameter(theta_bar_)}});
}

}  // namespace icobrdf
