#include "icobrdf/core/models/albedo_quadrature.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "icobrdf/core/grid/gauss_legendre.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

// Node counts beyond this are a typing error, not a finer rule (4096^2 pairs per sun direction).
constexpr int kMaxAlbedoNodes = 4096;
// 90 degrees converted to radians may round a few ulps above pi/2: still the horizon.
constexpr double kZenithSlack = 1e-12;

// Gauss-Legendre nodes of the panels [edges(k), edges(k+1)] (empty panels skipped), `n` per panel.
void append_panels(const std::vector<double>& edges, int n, std::vector<double>& nodes, std::vector<double>& weights) {
  for (size_t k = 0; k + 1 < edges.size(); ++k) {
    if (!(edges[k + 1] > edges[k])) continue;
    const QuadratureRule r = gauss_legendre(n, edges[k], edges[k + 1]);
    for (Eigen::Index j = 0; j < r.nodes.size(); ++j) {
      nodes.push_back(r.nodes(j));
      weights.push_back(r.weights(j));
    }
  }
}

// Sum of the delta parts' weights: their directional albedo at every incidence.
double delta_albedo(const BrdfModel& model) {
  double sum = 0.0;
  for (const auto& d : model.delta_parts()) sum += d.weight;
  return sum;
}

// a at one sun zenith: the mean over the sun azimuths (one for an isotropic model) of the view quadrature.
Eigen::RowVectorXd albedo_at(const BrdfModel& model, double theta_s, const AlbedoRule& rule) {
  const int azimuths = model.is_isotropic() ? 1 : rule.sun_azimuths;
  Eigen::RowVectorXd sum = Eigen::RowVectorXd::Zero(model.channels());
  Eigen::MatrixXd values;
  for (int k = 0; k < azimuths; ++k) {
    const double phi_s = 2.0 * M_PI * k / azimuths;
    const ViewNodes v = black_sky_nodes(theta_s, phi_s, rule);
    values.resize(v.directions.rows(), model.channels());
    const Eigen::Vector3d ws(std::sin(theta_s) * std::cos(phi_s), std::sin(theta_s) * std::sin(phi_s), std::cos(theta_s));
    model.eval_row(ws, v.directions, values);
    sum += v.weights.transpose() * values;
  }
  return sum / azimuths + Eigen::RowVectorXd::Constant(model.channels(), delta_albedo(model));
}

}  // namespace

void check_albedo_rule(const AlbedoRule& rule) {
  const std::pair<const char*, int> counts[] = {{"polar_nodes", rule.polar_nodes},
                                                {"azimuth_nodes", rule.azimuth_nodes},
                                                {"sun_polar_nodes", rule.sun_polar_nodes},
                                                {"sun_azimuths", rule.sun_azimuths}};
  for (const auto& [name, n] : counts)
    if (n < 1 || n > kMaxAlbedoNodes)
      throw ArgumentError(std::string("albedo quadrature: ") + name + " must be in [1, " + std::to_string(kMaxAlbedoNodes) + "], found " +
                          std::to_string(n));
}

ViewNodes black_sky_nodes(double theta_s, double phi_s, const AlbedoRule& rule) {
  check_albedo_rule(rule);
  if (theta_s > M_PI / 2 && theta_s <= M_PI / 2 + kZenithSlack) theta_s = M_PI / 2;
  if (!(theta_s >= 0.0 && theta_s <= M_PI / 2))
    throw ArgumentError("albedo: solar zenith must be in [0, 90] degrees, found " + std::to_string(theta_s * 180.0 / M_PI));
  const double mu_s = std::cos(theta_s);
  std::vector<double> mu, wmu, psi, wpsi;
  // One panel of twice the nodes when the split point is an end (sun at the zenith or on the horizon).
  if (mu_s > 0.0 && mu_s < 1.0)
    append_panels({0.0, mu_s, 1.0}, rule.polar_nodes, mu, wmu);
  else
    append_panels({0.0, 1.0}, 2 * rule.polar_nodes, mu, wmu);
  append_panels({0.0, M_PI, 2.0 * M_PI}, rule.azimuth_nodes, psi, wpsi);
  ViewNodes v;
  const Eigen::Index n = static_cast<Eigen::Index>(mu.size() * psi.size());
  v.directions.resize(n, 3);
  v.weights.resize(n);
  Eigen::Index r = 0;
  for (size_t a = 0; a < mu.size(); ++a) {
    const double s = std::sqrt(std::max(0.0, 1.0 - mu[a] * mu[a]));
    for (size_t b = 0; b < psi.size(); ++b, ++r) {
      const double phi = phi_s + psi[b];
      v.directions.row(r) << s * std::cos(phi), s * std::sin(phi), mu[a];
      v.weights(r) = wmu[a] * wpsi[b] * mu[a];
    }
  }
  return v;
}

Eigen::MatrixXd black_sky_albedo(const BrdfModel& model, const Eigen::VectorXd& theta_s, const AlbedoRule& rule) {
  check_albedo_rule(rule);
  Eigen::MatrixXd out(theta_s.size(), model.channels());
  for (Eigen::Index k = 0; k < theta_s.size(); ++k) out.row(k) = albedo_at(model, theta_s(k), rule);
  return out;
}

Eigen::RowVectorXd white_sky_albedo(const BrdfModel& model, const AlbedoRule& rule) {
  check_albedo_rule(rule);
  const QuadratureRule gl = gauss_legendre(rule.sun_polar_nodes, 0.0, 1.0);
  Eigen::RowVectorXd sum = Eigen::RowVectorXd::Zero(model.channels());
  for (Eigen::Index k = 0; k < gl.nodes.size(); ++k) sum += 2.0 * gl.weights(k) * gl.nodes(k) * albedo_at(model, std::acos(gl.nodes(k)), rule);
  return sum;
}

}  // namespace icobrdf
