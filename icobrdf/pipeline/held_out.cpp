#include "icobrdf/pipeline/held_out.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/support/scramble.hpp"
#include "icobrdf/io/measured_sources.hpp"
#include "icobrdf/pipeline/keys.hpp"

namespace icobrdf {
namespace {

Eigen::Vector3d direction_deg(const std::pair<double, double>& theta_phi) {
  return direction_from_angles(theta_phi.first * M_PI / 180, theta_phi.second * M_PI / 180);
}

std::uint64_t seed_of(const std::string& what, const SceneMaterial& m) {
  return std::stoull(fnv1a_hex(what + "|" + m.name).substr(0, 15), nullptr, 16);
}

// The pairs and, for sources of samples, which samples they are (MERL: bins; CSV: sample indices).
struct Drawn {
  HeldOutPairs pairs;
  std::vector<std::int64_t> merl_bins;  // bins held out of a MERL table
  std::vector<bool> csv_held;           // per CSV sample: held out
  bool merl = false, csv = false;
};

// A MERL table's held-out pairs are its own samples: its lookup between them is piecewise constant (1-degree
// bins), so pairs elsewhere would measure the bins' steps rather than the data (GGX 0.2 written to a table: the
// table's lookup is 0.056 from the model it sampled, a rank-2 lobe fitted to its samples 0.026). Bins are drawn
// with probability proportional to their solid-angle measure (icobrdf/io/merl.hpp merl_samples), so that the plain
// relative L2 over the pairs estimates the measure-weighted error over the table; each pair is turned about
// the normal by a random azimuth (the table is isotropic). Every bin drawn is left out of the fits.
void draw_merl(const Scene& s, const SceneMaterial& m, const MerlTable& table, Drawn& d) {
  const MerlSamples smp = merl_samples(table);
  std::mt19937_64 rng(seed_of("holdout", m));
  const double zlo = std::cos(m.incidence_max * M_PI / 180), zhi = std::cos(m.incidence_min * M_PI / 180);
  Eigen::VectorXd w = smp.weights;
  for (Eigen::Index k = 0; k < w.size(); ++k)
    if (smp.wi(k, 2) < zlo || smp.wi(k, 2) > zhi) w(k) = 0.0;
  if (!(w.sum() > 0.0)) throw InputError("MERL table '" + table.path + "' has no valid sample in the material's incidence range");
  std::discrete_distribution<Eigen::Index> pick(w.data(), w.data() + w.size());
  std::uniform_real_distribution<double> turn(0.0, 2.0 * M_PI);
  HeldOutPairs& h = d.pairs;
  h.wi.resize(s.holdout_pairs, 3);
  h.wr.resize(s.holdout_pairs, 3);
  h.f.resize(s.holdout_pairs, smp.values.cols());
  for (int k = 0; k < s.holdout_pairs; ++k) {
    const Eigen::Index j = pick(rng);
    const double a = turn(rng), c = std::cos(a), sn = std::sin(a);
    h.wi.row(k) << c * smp.wi(j, 0) - sn * smp.wi(j, 1), sn * smp.wi(j, 0) + c * smp.wi(j, 1), smp.wi(j, 2);
    h.wr.row(k) << c * smp.wr(j, 0) - sn * smp.wr(j, 1), sn * smp.wr(j, 0) + c * smp.wr(j, 1), smp.wr(j, 2);
    h.f.row(k) = smp.values.row(j);
    d.merl_bins.push_back(smp.bins[static_cast<size_t>(j)]);
  }
  d.merl = true;
}

// CSV samples: the held_out_sample_count samples with the smallest splitmix64(seed + index) among those whose
// incidence lies in the material's range, seed = FNV-1a of "holdout|NAME"; a merged sample (weight = rows
// merged) is one pair per row. (Ranking FNV-1a of "holdout|NAME|INDEX" itself held out runs of 100
// consecutive samples: its high bits hardly depend on the last digits.)
void draw_csv(const Scene& s, const SceneMaterial& m, const BrdfSamples& smp, const std::string& spec, Drawn& d) {
  if (!m.lights.empty())
    throw ArgumentError("material '" + m.name + "': SOURCE '" + quoted_text(spec) +
                        "' holds scattered samples, which have no values at the scene's light x camera pairs: remove lights and cameras, its errors are measured on held-out samples");
  const double zlo = std::cos(m.incidence_max * M_PI / 180), zhi = std::cos(m.incidence_min * M_PI / 180);
  const Eigen::Index n = smp.wi.rows();
  const std::uint64_t seed = std::stoull(fnv1a_hex("holdout|" + m.name), nullptr, 16);
  std::vector<std::pair<std::uint64_t, Eigen::Index>> eligible;
  for (Eigen::Index k = 0; k < n; ++k)
    if (smp.wi(k, 2) >= zlo && smp.wi(k, 2) <= zhi) eligible.emplace_back(splitmix64(seed + static_cast<std::uint64_t>(k)), k);
  const long long count = held_out_sample_count(n, s.holdout_pairs);
  if (count < 1 || eligible.empty())
    throw InputError("material '" + m.name + "': SOURCE '" + quoted_text(spec) + "' has " + std::to_string(n) + " sample(s), " +
                     std::to_string(eligible.size()) + " in the incidence range; a held-out split needs at least " +
                     std::to_string(kHeldOutShare) + " samples with some in the range");
  const auto take = static_cast<size_t>(std::min<long long>(count, static_cast<long long>(eligible.size())));
  std::partial_sort(eligible.begin(), eligible.begin() + static_cast<std::ptrdiff_t>(take), eligible.end());
  d.csv_held.assign(static_cast<size_t>(n), false);
  Eigen::Index rows = 0;
  for (size_t k = 0; k < take; ++k) {
    d.csv_held[static_cast<size_t>(eligible[k].second)] = true;
    rows += static_cast<Eigen::Index>(std::llround(smp.weights(eligible[k].second)));
  }
  HeldOutPairs& h = d.pairs;
  h.wi.resize(rows, 3);
  h.wr.resize(rows, 3);
  h.f.resize(rows, smp.values.cols());
  Eigen::Index r = 0;
  for (size_t k = 0; k < take; ++k) {
    const Eigen::Index j = eligible[k].second;
    for (long long c = std::llround(smp.weights(j)); c > 0; --c, ++r) {
      h.wi.row(r) = smp.wi.row(j);
      h.wr.row(r) = smp.wr.row(j);
      h.f.row(r) = smp.values.row(j);
    }
  }
  d.csv = true;
}

Drawn draw(const Scene& s, const SceneMaterial& m, const BrdfSource& src) {
  Drawn d;
  if (const BrdfSamples* smp = samples_of(src)) {
    draw_csv(s, m, *smp, src.spec(), d);
    return d;
  }
  if (m.lights.empty())
    if (const MerlTable* table = merl_table_of(src)) {
      draw_merl(s, m, *table, d);
      return d;
    }
  HeldOutPairs& h = d.pairs;
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
    std::mt19937_64 rng(seed_of("holdout", m));
    const double zlo = std::cos(m.incidence_max * M_PI / 180), zhi = std::cos(m.incidence_min * M_PI / 180);
    h.wi.resize(s.holdout_pairs, 3);
    h.wr.resize(s.holdout_pairs, 3);
    for (int k = 0; k < s.holdout_pairs; ++k) {
      h.wi.row(k) = uniform_direction(rng, zlo, zhi).transpose();
      h.wr.row(k) = uniform_direction(rng).transpose();
    }
  }
  h.f = src.eval(h.wi, h.wr);
  return d;
}

}  // namespace

long long held_out_sample_count(long long samples, int holdout_pairs) {
  return std::min<long long>(holdout_pairs, samples / kHeldOutShare);
}

HeldOutPairs held_out_pairs(const Scene& s, const SceneMaterial& m, const BrdfSource& src) {
  return held_out_split(s, m, src).pairs;
}

HeldOutSplit held_out_split(const Scene& s, const SceneMaterial& m, const BrdfSource& src) {
  Drawn d = draw(s, m, src);
  const Eigen::MatrixXd& f = d.pairs.f;
  for (Eigen::Index k = 0; k < f.size(); ++k)
    if (!std::isfinite(f.data()[k])) throw InputError("source '" + quoted_text(src.spec()) + "' gives a non-finite value at a held-out pair");
  HeldOutSplit out;
  out.pairs = std::move(d.pairs);
  if (d.merl) out.training = merl_source_without(src, d.merl_bins);
  if (d.csv) out.training = samples_source_without(src, d.csv_held);
  return out;
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
