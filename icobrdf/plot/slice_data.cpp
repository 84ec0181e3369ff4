#include "icobrdf/plot/slice_data.hpp"

#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/projection/projection.hpp"

namespace icobrdf::plot {

Eigen::MatrixXd channel_mean(const Spectrum& s) {
  if (s.channels.empty()) throw ArgumentError("spectrum of '" + quoted_text(s.source) + "' has no channels");
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(s.channels[0].rows(), s.channels[0].cols());
  for (const auto& ch : s.channels) c += ch;
  return c / static_cast<double>(s.channels.size());
}

Eigen::MatrixXd truncated_coefficients(const Eigen::MatrixXd& c, int order, const LowPassFilter& filter) {
  const int m = hemisphere_basis_count(order);
  if (m > c.rows())
    throw ArgumentError("truncation order " + std::to_string(order) + " exceeds the spectrum's order " +
                        std::to_string(hemisphere_basis_order(static_cast<int>(c.rows()))));
  Eigen::MatrixXd t = c.topLeftCorner(m, m);
  if (filter.kind != LowPassFilter::Kind::None) t = filter_coefficients(t, order, filter);
  return t;
}

Eigen::VectorXd slice_values(const Eigen::MatrixXd& c, int order, const Eigen::Vector3d& wi, const RowMatrix3d& wr) {
  const int m = hemisphere_basis_count(order);
  Eigen::VectorXd ki(m);
  hemisphere_basis_eval(order, wi, ki.data());
  const Eigen::VectorXd u = c.transpose() * ki;
  return hemisphere_basis_matrix(order, wr) * u;
}

RowMatrix3d plane_of_incidence_directions(double phi_i, const Eigen::VectorXd& t) {
  RowMatrix3d d(t.size(), 3);
  const double cx = std::cos(phi_i), cy = std::sin(phi_i);
  for (Eigen::Index k = 0; k < t.size(); ++k) {
    const double s = std::sin(t[k]);
    d.row(k) << -s * cx, -s * cy, std::max(0.0, std::cos(t[k]));
  }
  return d;
}

}  // namespace icobrdf::plot
