#include "icobrdf/pipeline/held_out.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <random>
#include <string>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/pipeline/exchanged_pairs.hpp"
#include "icobrdf/pipeline/keys.hpp"

namespace icobrdf {
namespace {

Eigen::Vector3d direction_deg(const std::pair<double, double>& theta_phi) {
  return direction_from_angles(theta_phi.first * M_PI / 180, theta_phi.second * M_PI / 180);
}

std::uint64_t seed_of(const std::string& what, const SceneMaterial& m) {
  return std::stoull(fnv1a_hex(what + "|" + m.name).substr(0, 15), nullptr, 16);
}

// The pairs and, for a source judged at its own samples, the source without them.
struct Drawn {
  HeldOutPairs pairs;
  std::unique_ptr<BrdfSource> training;
};

Drawn draw(const Scene& s, const SceneMaterial& m, const BrdfSource& src) {
  Drawn d;
  HeldOutRequest request;
  request.material = m.name;
  request.pairs = s.holdout_pairs;
  request.incidence_min_deg = m.incidence_min;
  request.incidence_max_deg = m.incidence_max;
  request.lights_and_cameras = !m.lights.empty();
  if (auto own = src.own_held_out(request)) {
    d.pairs = std::move(own->pairs);
    d.training = std::move(own->training);
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

Eigen::VectorXd metric_weights(const HeldOutPairs& h, ErrorMetric metric) {
  return metric == ErrorMetric::Cosine ? Eigen::VectorXd(h.wi.col(2).cwiseProduct(h.wr.col(2))) : Eigen::VectorXd::Ones(h.wi.rows());
}

// |w (f - (f + f^T)/2)| / |w f| over all rows; 0 when the reference norm is 0.
double asymmetry_of(const Eigen::MatrixXd& f, const Eigen::MatrixXd& ft, const Eigen::VectorXd& w) {
  const double ref = (w.asDiagonal() * f).norm();
  const double anti = (w.asDiagonal() * (f - ft)).norm() / 2;
  return ref > 0 ? anti / ref : 0.0;
}

// Samples judged at their own values: the exchanged values where two held-out samples are each other's
// exchange (kSwapToleranceDeg, icobrdf/pipeline/exchanged_pairs.hpp). Returns the rows matched and fills ft there.
std::vector<Eigen::Index> exchanged_samples(const HeldOutPairs& h, Eigen::MatrixXd& ft) {
  const std::vector<Eigen::Index> partner = exchanged_partners(h.wi, h.wr, kSwapToleranceDeg);
  std::vector<Eigen::Index> matched;
  ft = h.f;
  for (Eigen::Index k = 0; k < h.wi.rows(); ++k) {
    const Eigen::Index l = partner[static_cast<size_t>(k)];
    if (l < 0) continue;
    ft.row(k) = h.f.row(l);
    matched.push_back(k);
  }
  return matched;
}

}  // namespace

double noise_figure(const BrdfSource& src, const PairValues& h, const Eigen::VectorXd& w) {
  const std::optional<Eigen::MatrixXd> sigma = src.noise_sigma_at(h.wi, h.wr);
  const double ref = (w.asDiagonal() * h.f).norm();
  if (!sigma || h.f.size() == 0 || !(ref > 0)) return std::nan("");
  return (w.asDiagonal() * *sigma).norm() / ref;
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
  out.training = std::move(d.training);
  HeldOutPairs& h = out.pairs;
  const Eigen::VectorXd w = metric_weights(h, m.metric);
  out.noise = noise_figure(src, h, w);
  if (src.reciprocal_by_construction()) return out;
  if (!src.judged_at_own_samples()) {
    const Eigen::MatrixXd ft = src.eval(h.wr, h.wi);
    for (Eigen::Index k = 0; k < ft.size(); ++k)
      if (!std::isfinite(ft.data()[k]))
        throw InputError("source '" + quoted_text(src.spec()) + "' gives a non-finite value at an exchanged held-out pair");
    out.asymmetry = asymmetry_of(h.f, ft, w);
    if (m.reciprocal) {
      h.f = (h.f + ft) / 2;
      out.reciprocal_reference = true;
    }
    return out;
  }
  Eigen::MatrixXd ft;
  const std::vector<Eigen::Index> rows = exchanged_samples(h, ft);
  if (rows.empty()) {
    out.asymmetry = std::nan("");
    return out;
  }
  const auto n = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd fm(n, h.f.cols()), gm(n, h.f.cols());
  Eigen::VectorXd wm(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    fm.row(k) = h.f.row(rows[static_cast<size_t>(k)]);
    gm.row(k) = ft.row(rows[static_cast<size_t>(k)]);
    wm[k] = w[rows[static_cast<size_t>(k)]];
  }
  out.asymmetry = asymmetry_of(fm, gm, wm);
  if (m.reciprocal) {
    for (const Eigen::Index k : rows) h.f.row(k) = (h.f.row(k) + ft.row(k)) / 2;  // ft.row(k) is another row's f
    out.reciprocal_reference = true;
  }
  return out;
}

HeldOutErrors::HeldOutErrors(const HeldOutPairs& pairs, int max_order, ErrorMetric metric, bool reciprocal_reference)
    : pairs_(&pairs), reciprocal_reference_(reciprocal_reference) {
  ki_ = hemisphere_basis_matrix(max_order, pairs.wi);
  kr_ = hemisphere_basis_matrix(max_order, pairs.wr);
  w_ = metric_weights(pairs, metric);
  const Eigen::MatrixXd wf = w_.asDiagonal() * pairs.f;
  ref_norm_ = wf.norm();
  ref_max_ = wf.cwiseAbs().maxCoeff();
  const double z = std::cos(kGrazingDeg * M_PI / 180);
  double grazing = 0.0;
  for (Eigen::Index k = 0; k < wf.rows(); ++k)
    if (pairs.wi(k, 2) < z || pairs.wr(k, 2) < z) grazing += wf.row(k).squaredNorm();
  grazing_share_ = ref_norm_ > 0 ? grazing / (ref_norm_ * ref_norm_) : 0.0;
}

Eigen::MatrixXd HeldOutErrors::reference_at(const BrdfSource& source, const RowMatrix3d& wi, const RowMatrix3d& wr) const {
  Eigen::MatrixXd f = source.eval(wi, wr);
  if (reciprocal_reference_ && !source.judged_at_own_samples()) f = (f + source.eval(wr, wi)) / 2;
  return f;
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
