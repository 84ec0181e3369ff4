#include "icobrdf/pipeline/held_out.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "icobrdf/core/direction.hpp"
#include "icobrdf/core/error.hpp"
#include "icobrdf/core/hemisphere_basis.hpp"
#include "icobrdf/io/measured_sources.hpp"
#include "icobrdf/pipeline/keys.hpp"

namespace icobrdf {
namespace {

Eigen::Vector3d direction_deg(const std::pair<double, double>& theta_phi) {
  return direction_from_angles(theta_phi.first * M_PI / 180, theta_phi.second * M_PI / 180);
}

// A MERL table is judged at its own samples: its lookup between them is piecewise constant (1-degree bins),
// so pairs elsewhere would measure the bins' steps rather than the data (GGX 0.2 written to a table: the
// table's lookup is 0.056 from the model it sampled, a rank-2 lobe fitted to its samples 0.026). Bins are drawn
// with probability proportional to their solid-angle measure (icobrdf/io/merl.hpp merl_samples), so that the plain
// relative L2 over the pairs estimates the measure-weighted error over the table; each pair is turned about
// the normal by a random azimuth (the table is isotropic).
HeldOutPairs merl_held_out_pairs(const Scene& s, const SceneMaterial& m, const MerlTable& table) {
  const MerlSamples smp = merl_samples(table);
  std::mt19937_64 rng(std::stoull(fnv1a_hex("holdout|" + m.name).substr(0, 15), nullptr, 16));
  const double zlo = std::cos(m.incidence_max * M_PI / 180), zhi = std::cos(m.incidence_min * M_PI / 180);
  Eigen::VectorXd w = smp.weights;
  for (Eigen::Index k = 0; k < w.size(); ++k)
    if (smp.wi(k, 2) < zlo || smp.wi(k, 2) > zhi) w(k) = 0.0;
  if (!(w.sum() > 0.0)) throw InputError("MERL table '" + table.path + "' has no valid sample in the material's incidence range");
  std::discrete_distribution<Eigen::Index> pick(w.data(), w.data() + w.size());
  std::uniform_real_distribution<double> turn(0.0, 2.0 * M_PI);
  HeldOutPairs h;
  h.wi.resize(s.holdout_pairs, 3);
  h.wr.resize(s.holdout_pairs, 3);
  h.f.resize(s.holdout_pairs, smp.values.cols());
  for (int k = 0; k < s.holdout_pairs; ++k) {
    const Eigen::Index j = pick(rng);
    const double a = turn(rng), c = std::cos(a), sn = std::sin(a);
    h.wi.row(k) << c * smp.wi(j, 0) - sn * smp.wi(j, 1), sn * smp.wi(j, 0) + c * smp.wi(j, 1), smp.wi(j, 2);
    h.wr.row(k) << c * smp.wr(j, 0) - sn * smp.wr(j, 1), sn * smp.wr(j, 0) + c * smp.wr(j, 1), smp.wr(j, 2);
    h.f.row(k) = smp.values.row(j);
  }
  return h;
}

}  // namespace

HeldOutPairs held_out_pairs(const Scene& s, const SceneMaterial& m, const BrdfSource& src) {
  if (m.lights.empty())
    if (const MerlTable* table = merl_table_of(src)) return merl_held_out_pairs(s, m, *table);
  HeldOutPairs h;
  if (!m.lights.empty()) {
    const auto n = static_cast<Eigen::Index>(m.lights.size() * m.cameras.size());
    h.wi.resize(n, 3);
    h.wr.resize(n, 3);
    Eigen::Index k = 0;
    for (const auto& l : m.lights)
      for (const auto& c : m.cameras) {
        h.wi.row(k) = direction_deg(l).transpose();
        h.wr.row(k++) = direction_deg(c).transpose();
      }
  } else {
    // Uniform in solid angle: z = cos(theta) uniform. Seeded by the material's name: reproducible.
    std::mt19937_64 rng(std::stoull(fnv1a_hex("holdout|" + m.name).substr(0, 15), nullptr, 16));
    const double zlo = std::cos(m.incidence_max * M_PI / 180), zhi = std::cos(m.incidence_min * M_PI / 180);
    h.wi.resize(s.holdout_pairs, 3);
    h.wr.resize(s.holdout_pairs, 3);
    for (int k = 0; k < s.holdout_pairs; ++k) {
      h.wi.row(k) = uniform_direction(rng, zlo, zhi).transpose();
      h.wr.row(k) = uniform_direction(rng).transpose();
    }
  }
  h.f = src.eval(h.wi, h.wr);
  for (Eigen::Index k = 0; k < h.f.size(); ++k)
    if (!std::isfinite(h.f.data()[k])) throw InputError("source '" + quoted_text(src.spec()) + "' gives a non-finite value at a held-out pair");
  return h;
}

HeldOutErrors::HeldOutErrors(const HeldOutPairs& pairs, int max_order, ErrorMetric metric) : pairs_(&pairs) {
  ki_ = hemisphere_basis_matrix(max_order, pairs.wi);
  kr_ = hemisphere_basis_matrix(max_order, pairs.wr);
  w_ = metric == ErrorMetric::Cosine ? Eigen::VectorXd(pairs.wi.col(2).cwiseProduct(pairs.wr.col(2)))
                                     : Eigen::VectorXd::Ones(pairs.wi.rows());
  const Eigen::MatrixXd wf = w_.asDiagonal() * pairs.f;
  ref_norm_ = wf.norm();
  ref_max_ = wf.cwiseAbs().maxCoeff();
}

HeldOutError HeldOutErrors::operator()(const std::vector<Eigen::MatrixXd>& c, int order) const {
  return of_values(modes_values(c, order));
}

Eigen::MatrixXd HeldOutErrors::modes_values(const std::vector<Eigen::MatrixXd>& c, int order) const {
  const int m = hemisphere_basis_count(order);
  Eigen::MatrixXd out(ki_.rows(), static_cast<Eigen::Index>(c.size()));
  for (size_t ch = 0; ch < c.size(); ++ch)
    out.col(static_cast<Eigen::Index>(ch)) =
        ((ki_.leftCols(m) * c[ch].topLeftCorner(m, m)).array() * kr_.leftCols(m).array()).rowwise().sum();
  return out;
}

HeldOutError HeldOutErrors::of_values(const Eigen::MatrixXd& fit) const {
  double sq = 0.0, mx = 0.0;
  for (Eigen::Index ch = 0; ch < fit.cols(); ++ch) {
    const Eigen::VectorXd d = w_.cwiseProduct(fit.col(ch) - pairs_->f.col(ch));
    sq += d.squaredNorm();
    mx = std::max(mx, d.cwiseAbs().maxCoeff());
  }
  return {ref_norm_ > 0 ? std::sqrt(sq) / ref_norm_ : std::sqrt(sq), ref_max_ > 0 ? mx / ref_max_ : mx};
}

std::vector<Eigen::MatrixXd> truncate_channels(const std::vector<Eigen::MatrixXd>& c, int order) {
  const int m = hemisphere_basis_count(order);
  std::vector<Eigen::MatrixXd> out;
  for (const auto& x : c) out.push_back(x.topLeftCorner(m, m));
  return out;
}

}  // namespace icobrdf
