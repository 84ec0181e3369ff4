#include "icobrdf/core/fit/lobe_axes.hpp"

#include <Eigen/Dense>

#include <cmath>

namespace icobrdf {

LobeAxes estimate_lobe_axes(const PairSampler& sampler, int channels) {
  LobeAxes out;
  const int n = 1 + kLobeAzimuths * kLobeSteps;
  RowMatrix3d w(n, 3);
  w.row(0) << 0.0, 0.0, 1.0;
  const double tmax = std::sqrt(kLobeMaxTheta / (0.5 * M_PI));
  std::vector<double> theta(kLobeSteps + 1, 0.0);
  for (int s = 1; s <= kLobeSteps; ++s) {
    const double t = tmax * s / kLobeSteps;
    theta[s] = 0.5 * M_PI * t * t;
  }
  for (int a = 0; a < kLobeAzimuths; ++a) {
    const double psi = 2.0 * M_PI * a / kLobeAzimuths;
    for (int s = 1; s <= kLobeSteps; ++s)
      w.row(1 + a * kLobeSteps + s - 1) << std::sin(theta[s]) * std::cos(psi), std::sin(theta[s]) * std::sin(psi),
          std::cos(theta[s]);
  }
  Eigen::MatrixXd f(n, channels);
  sampler(w, w, f);
  const Eigen::VectorXd p = f.rowwise().sum();
  const double half = 0.5 * p(0);
  if (!(p(0) > 0.0) || !std::isfinite(p(0))) {
    out.why = "the probe f(n, n) is not positive";
    return out;
  }
  Eigen::MatrixXd M(kLobeAzimuths, 3);
  Eigen::VectorXd r(kLobeAzimuths);
  for (int a = 0; a < kLobeAzimuths; ++a) {
    double prev_value = p(0), prev_slope = 0.0, radius = -1.0;
    for (int s = 1; s <= kLobeSteps && radius < 0.0; ++s) {
      const double value = p(1 + a * kLobeSteps + s - 1), slope = std::tan(theta[s]);
      if (!std::isfinite(value)) break;
      if (value <= half) radius = prev_slope + (slope - prev_slope) * (prev_value - half) / (prev_value - value);
      prev_value = value, prev_slope = slope;
    }
    if (radius <= 0.0) {
      out.why = "the probe does not fall to half its value at h = n within 80 degrees";
      return out;
    }
    const double psi = 2.0 * M_PI * a / kLobeAzimuths, x = radius * std::cos(psi), y = radius * std::sin(psi);
    M.row(a) << x * x, 2.0 * x * y, y * y;
    r(a) = radius;
  }
  const Eigen::Vector3d abc = M.colPivHouseholderQr().solve(Eigen::VectorXd::Ones(kLobeAzimuths));
  Eigen::Matrix2d A;
  A << abc(0), abc(1), abc(1), abc(2);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(A);
  if (!(eig.eigenvalues()(0) > 0.0)) {
    out.why = "the half-maximum contour is not an ellipse";
    return out;
  }
  double ss = 0.0;
  for (int a = 0; a < kLobeAzimuths; ++a) {
    const double psi = 2.0 * M_PI * a / kLobeAzimuths;
    const Eigen::Vector2d e(std::cos(psi), std::sin(psi));
    const double fitted = 1.0 / std::sqrt(e.dot(A * e));
    ss += std::pow((fitted - r(a)) / r(a), 2);
  }
  out.residual = std::sqrt(ss / kLobeAzimuths);
  if (out.residual > kLobeEllipseTolerance) {
    out.why = "the half-maximum contour is not elliptical (rms deviation " + std::to_string(out.residual) + ")";
    return out;
  }
  // Smallest eigenvalue: the wide axis.
  const Eigen::Vector2d v = eig.eigenvectors().col(0);
  double axis = std::atan2(v.y(), v.x());
  if (axis <= -0.5 * M_PI) axis += M_PI;
  if (axis > 0.5 * M_PI) axis -= M_PI;
  out.axis = axis;
  out.wide = 1.0 / std::sqrt(eig.eigenvalues()(0));
  out.narrow = 1.0 / std::sqrt(eig.eigenvalues()(1));
  out.found = true;
  return out;
}

}  // namespace icobrdf
