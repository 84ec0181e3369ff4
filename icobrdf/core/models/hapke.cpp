#include "icobrdf/core/models/hapke.hpp"

#include "icobrdf/core/grid/gauss_legendre.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

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

double HapkeModel::value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const {
  return w_ / (4.0 * M_PI) * h_(wi.z()) * h_(wr.z()) / std::max(wi.z() + wr.z(), kGrazingCosFloor);
}

std::string HapkeModel::spec() const { return format_model_spec("hapke", {{"w", format_parameter(w_)}}); }

}  // namespace icobrdf
