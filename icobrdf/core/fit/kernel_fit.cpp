#include "icobrdf/core/fit/kernel_fit.hpp"

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <utility>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/grid/gauss_legendre.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

constexpr double kKernelNaN = std::numeric_limits<double>::quiet_NaN();

// Least squares of W^(1/2) K p = W^(1/2) Y by the SVD (3 columns): weights, (K^T W K)^+ and the condition.
struct KernelSolve {
  Eigen::MatrixXd p;
  Eigen::Matrix3d inverse_gram;
  double condition = 0.0;
};

KernelSolve solve_kernel_ls(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd s = svd.singularValues();
  KernelSolve out;
  // Fewer rows than weights leave a null space the thin SVD does not show.
  out.condition = a.rows() >= a.cols() && s(s.size() - 1) > 0.0 ? s(0) / s(s.size() - 1) : std::numeric_limits<double>::infinity();
  const double tau = s(0) / kMaxDeterminedCondition;  // values below are the undetermined combinations
  Eigen::VectorXd inv = Eigen::VectorXd::Zero(s.size());
  for (Eigen::Index k = 0; k < s.size(); ++k)
    if (s(k) > tau) inv(k) = 1.0 / s(k);
  out.p = svd.matrixV() * inv.asDiagonal() * svd.matrixU().transpose() * b;
  out.inverse_gram = svd.matrixV() * inv.cwiseProduct(inv).asDiagonal() * svd.matrixV().transpose();
  return out;
}

const char* kernel_volume_name(VolumeKernel k) { return k == VolumeKernel::RossThick ? "thick" : "thin"; }
const char* kernel_geometric_name(GeometricKernel k) { return k == GeometricKernel::LiSparseR ? "sparse" : "dense"; }

}  // namespace

Eigen::Vector3d kernel_row(const KernelChoice& kernels, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) {
  return {1.0, ross_kernel(kernels.volume, wi, wr), li_kernel(kernels.geometric, wi, wr)};
}

Eigen::Vector3d black_sky_kernel_integrals(const KernelChoice& kernels, double sza) {
  // (1/pi) integral K cos(vza) dOmega_r = (2/pi) integral_0^1 dmu integral_0^pi dphi K(sza, vza, phi) mu (K is even in raa).
  const QuadratureRule mu = gauss_legendre(kKernelIntegralNodes, 0.0, 1.0);
  const QuadratureRule phi = gauss_legendre(kKernelIntegralNodes, 0.0, M_PI);
  const Eigen::Vector3d wi = direction_from_angles(sza, 0.0);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (Eigen::Index a = 0; a < mu.nodes.size(); ++a) {
    const double vza = std::acos(mu.nodes(a));
    for (Eigen::Index b = 0; b < phi.nodes.size(); ++b)
      sum += (mu.weights(a) * phi.weights(b) * mu.nodes(a)) * kernel_row(kernels, wi, direction_from_angles(vza, phi.nodes(b)));
  }
  return sum * (2.0 / M_PI);
}

Eigen::Vector3d white_sky_kernel_integrals(const KernelChoice& kernels) {
  // Computed once per kernel pair (a few tenths of a second) and kept.
  static std::mutex lock;
  static std::map<std::pair<int, int>, Eigen::Vector3d> done;
  const std::pair<int, int> key{static_cast<int>(kernels.volume), static_cast<int>(kernels.geometric)};
  {
    const std::lock_guard<std::mutex> hold(lock);
    if (const auto it = done.find(key); it != done.end()) return it->second;
  }
  const QuadratureRule mu = gauss_legendre(kKernelIntegralNodes, 0.0, 1.0);
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (Eigen::Index a = 0; a < mu.nodes.size(); ++a)
    sum += (2.0 * mu.weights(a) * mu.nodes(a)) * black_sky_kernel_integrals(kernels, std::acos(mu.nodes(a)));
  const std::lock_guard<std::mutex> hold(lock);
  done[key] = sum;
  return sum;
}

std::string KernelFit::spec(int channel) const {
  return format_model_spec("ross-li", {{"iso", format_parameter(weights(0, channel))},
                                       {"vol", format_parameter(weights(1, channel))},
                                       {"geo", format_parameter(weights(2, channel))},
                                       {"volume", kernel_volume_name(kernels.volume)},
                                       {"geometric", kernel_geometric_name(kernels.geometric)}});
}

KernelFit fit_kernel_weights(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                             const Eigen::VectorXd& weights, const KernelChoice& kernels, int folds) {
  const Eigen::Index n = wi.rows(), ch = values.cols();
  if (wr.rows() != n || values.rows() != n || weights.size() != n || ch < 1)
    throw ArgumentError("kernel fit: " + std::to_string(n) + " incident directions, " + std::to_string(wr.rows()) +
                        " remitted, " + std::to_string(values.rows()) + " value rows and " + std::to_string(weights.size()) +
                        " weights, expected one of each per sample and at least one channel");
  if (!values.allFinite() || !weights.allFinite() || (weights.array() < 0.0).any())
    throw ArgumentError("kernel fit: values and weights must be finite, weights >= 0");
  if (folds < 2) throw ArgumentError("kernel fit: expected at least 2 cross-validation folds, got " + std::to_string(folds));
  // The rows of positive weight, scaled by sqrt(w): W^(1/2) K and W^(1/2) Y (BRF).
  std::vector<Eigen::Index> rows;
  for (Eigen::Index s = 0; s < n; ++s)
    if (weights(s) > 0.0) rows.push_back(s);
  if (rows.empty()) throw ArgumentError("kernel fit: no sample with positive weight");
  const auto m = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd a(m, 3), b(m, ch);
  std::vector<int> fold(rows.size());
  double weight_sum = 0.0, zenith_sum = 0.0;
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index s = rows[static_cast<size_t>(k)];
    const double r = std::sqrt(weights(s));
    a.row(k) = r * kernel_row(kernels, wi.row(s).transpose(), wr.row(s).transpose()).transpose();
    b.row(k) = (r * M_PI) * values.row(s);
    fold[static_cast<size_t>(k)] = cross_validation_fold(k, folds);
    weight_sum += weights(s);
    zenith_sum += weights(s) * std::acos(std::clamp(wi(s, 2), -1.0, 1.0));
  }
  KernelFit out;
  out.kernels = kernels;
  out.samples = m;
  const KernelSolve all = solve_kernel_ls(a, b);
  out.weights = all.p;
  out.inverse_gram = all.inverse_gram;
  out.condition = all.condition;
  out.determined = all.condition <= kMaxDeterminedCondition;
  const Eigen::MatrixXd residual = a * all.p - b;  // sqrt(w) (fit - y), BRF
  out.residual_rms = (residual.colwise().squaredNorm().transpose() / weight_sum).cwiseSqrt() / M_PI;
  out.noise_sigma = m > 3 ? Eigen::VectorXd((residual.colwise().squaredNorm().transpose() / static_cast<double>(m - 3)).cwiseSqrt())
                          : Eigen::VectorXd::Constant(ch, kKernelNaN);
  // K-fold cross-validation on the modes' folds.
  double sse = 0.0;
  bool every_fold = true;
  for (int f = 0; f < folds && every_fold; ++f) {
    std::vector<Eigen::Index> train, held;
    for (Eigen::Index k = 0; k < m; ++k) (fold[static_cast<size_t>(k)] == f ? held : train).push_back(k);
    if (held.empty()) continue;
    if (train.size() < 3) {
      every_fold = false;
      break;
    }
    const KernelSolve t = solve_kernel_ls(a(train, Eigen::all), b(train, Eigen::all));
    if (!(t.condition <= kMaxDeterminedCondition)) every_fold = false;
    sse += (a(held, Eigen::all) * t.p - b(held, Eigen::all)).squaredNorm();
  }
  out.cv_folds = folds;
  out.cv_rms = every_fold ? std::sqrt(sse / (weight_sum * static_cast<double>(ch))) / M_PI : kKernelNaN;
  // Quantities and their weights of determination.
  out.solar_zenith = zenith_sum / weight_sum;
  const auto quantity = [&](const std::string& name, const Eigen::Vector3d& u) {
    KernelQuantity q;
    q.name = name;
    q.u = u;
    q.value = all.p.transpose() * u;
    q.inflation = u.dot(all.inverse_gram * u);
    q.sigma = out.noise_sigma * std::sqrt(q.inflation);
    out.quantities.push_back(q);
  };
  quantity("white-sky albedo", white_sky_kernel_integrals(kernels));
  quantity("black-sky albedo", black_sky_kernel_integrals(kernels, out.solar_zenith));
  quantity("nadir BRF", kernel_row(kernels, direction_from_angles(out.solar_zenith, 0.0), Eigen::Vector3d::UnitZ()));
  return out;
}

std::string supported_fit(double kernel_cv_rms, double modes_cv_rms) {
  if (std::isnan(kernel_cv_rms) || std::isnan(modes_cv_rms)) return "undecided";
  return kernel_cv_rms * kernel_cv_rms <= modes_cv_rms * modes_cv_rms * (1.0 + kCvTieFraction) ? "kernels" : "modes";
}

}  // namespace icobrdf
