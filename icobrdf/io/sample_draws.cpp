#include "icobrdf/io/sample_draws.hpp"

#include <fmt/core.h>

#include <cmath>
#include <random>

#include "icobrdf/core/basis/direction.hpp"

namespace icobrdf {

MaterialSamples draw_material_samples(const MaterialSampler& sampler, const Eigen::Vector3d& wi, long long n, std::uint64_t seed) {
  const IncidentDistribution dist = sampler.distribution(wi);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::VectorXd u1(n), u2(n);
  for (long long i = 0; i < n; ++i) u1[i] = uniform(rng), u2[i] = uniform(rng);
  return sampler.sample(dist, u1, u2);
}

std::string material_samples_csv(const MaterialSampler& sampler, const MaterialSamples& s) {
  std::string text = "theta_r,phi_r,pdf";
  for (const std::string& c : channel_column_names(sampler.source())) text += ",weight" + c.substr(1);  // "f_r" -> "weight_r"
  text += "\n";
  for (Eigen::Index i = 0; i < s.directions.rows(); ++i) {
    const Angles a = angles_from_direction(s.directions.row(i).transpose());
    text += fmt::format("{},{},{}", a.theta * 180 / M_PI, a.phi * 180 / M_PI, s.pdf[i]);
    for (Eigen::Index c = 0; c < s.weight.cols(); ++c) text += fmt::format(",{}", s.weight(i, c));
    text += "\n";
  }
  return text;
}

}  // namespace icobrdf
