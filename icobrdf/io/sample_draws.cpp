#include "icobrdf/io/sample_draws.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <random>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

// The next `n` draws from `rng`: u1 then u2 of each draw in turn.
MaterialSamples draw_block(const MaterialSampler& sampler, const IncidentDistribution& dist, long long n, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::VectorXd u1(n), u2(n);
  for (long long i = 0; i < n; ++i) u1[i] = uniform(rng), u2[i] = uniform(rng);
  return sampler.sample(dist, u1, u2);
}

std::string samples_csv_header(const MaterialSampler& sampler) {
  std::string text = "theta_r,phi_r,pdf";
  for (const std::string& c : channel_column_names(sampler.source())) text += ",weight" + c.substr(1);  // "f_r" -> "weight_r"
  return text + "\n";
}

std::string samples_csv_rows(const MaterialSamples& s) {
  std::string text;
  for (Eigen::Index i = 0; i < s.directions.rows(); ++i) {
    const Angles a = angles_from_direction(s.directions.row(i).transpose());
    text += fmt::format("{},{},{}", a.theta * 180 / M_PI, a.phi * 180 / M_PI, s.pdf[i]);
    for (Eigen::Index c = 0; c < s.weight.cols(); ++c) text += fmt::format(",{}", s.weight(i, c));
    text += "\n";
  }
  return text;
}

// UnsupportedError naming the first draw (counted from 0 over the whole run) whose weight is not finite.
void require_finite_weights(const MaterialSampler& sampler, const MaterialSamples& s, long long first) {
  for (Eigen::Index i = 0; i < s.weight.rows(); ++i)
    for (Eigen::Index c = 0; c < s.weight.cols(); ++c)
      if (!std::isfinite(s.weight(i, c)))
        throw UnsupportedError(fmt::format("{}: the weight of draw {} is {} (f at the drawn direction is not finite); nothing was written",
                                           sampler.source().spec(), first + i, s.weight(i, c)));
}

}  // namespace

bool write_material_samples_csv(std::ostream& out, const MaterialSampler& sampler, const Eigen::Vector3d& wi, long long n,
                                std::uint64_t seed) {
  const IncidentDistribution dist = sampler.distribution(wi);
  if (n <= kSampleDrawBlock) {  // one block: drawn and checked once
    std::mt19937_64 rng(seed);
    const MaterialSamples s = draw_block(sampler, dist, n, rng);
    require_finite_weights(sampler, s, 0);
    out << samples_csv_header(sampler) << samples_csv_rows(s);
    return static_cast<bool>(out);
  }
  std::mt19937_64 check(seed);
  for (long long first = 0; first < n; first += kSampleDrawBlock)
    require_finite_weights(sampler, draw_block(sampler, dist, std::min(kSampleDrawBlock, n - first), check), first);
  std::mt19937_64 rng(seed);
  out << samples_csv_header(sampler);
  for (long long first = 0; first < n && out; first += kSampleDrawBlock)
    out << samples_csv_rows(draw_block(sampler, dist, std::min(kSampleDrawBlock, n - first), rng));
  return static_cast<bool>(out);
}

}  // namespace icobrdf
