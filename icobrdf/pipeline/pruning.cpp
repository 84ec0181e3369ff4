#include "icobrdf/pipeline/pruning.hpp"

#include <algorithm>
#include <numeric>
#include <vector>

#include "icobrdf/core/basis/antisymmetric_modes.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"

namespace icobrdf {
namespace {

// A spectrum's channels as mode coefficient vectors (the symmetric modes, then the antisymmetric ones when the
// spectrum has them), ranked by magnitude; with_kept(k) rebuilds the channels from the k largest.
class RankedCoefficients {
 public:
  explicit RankedCoefficients(const Spectrum& s) : s_(s), anti_(has_antisymmetric_terms(s)) {
    for (const auto& c : s.channels) {
      Eigen::VectorXd v = s.isotropic ? ibsss_from_coefficients(c) : bsss_from_coefficients(c);
      symmetric_ = v.size();
      if (anti_) {
        const Eigen::VectorXd z = s.isotropic ? isotropic_antisymmetric_from_coefficients(c) : antisymmetric_from_coefficients(c);
        v.conservativeResize(symmetric_ + z.size());
        v.tail(z.size()) = z;
      }
      v_.push_back(std::move(v));
    }
    const Eigen::Index total = v_[0].size();
    Eigen::VectorXd mag = Eigen::VectorXd::Zero(total);
    for (const auto& v : v_) mag = mag.cwiseMax(v.cwiseAbs());
    rank_.resize(static_cast<size_t>(total));
    std::iota(rank_.begin(), rank_.end(), 0);
    std::stable_sort(rank_.begin(), rank_.end(), [&](Eigen::Index a, Eigen::Index b) { return mag[a] > mag[b]; });
  }
  Eigen::Index total() const { return static_cast<Eigen::Index>(rank_.size()); }
  std::vector<Eigen::MatrixXd> with_kept(Eigen::Index kept) const {
    std::vector<Eigen::MatrixXd> out;
    for (const auto& v : v_) {
      Eigen::VectorXd w = Eigen::VectorXd::Zero(total());
      for (Eigen::Index k = 0; k < kept; ++k) w[rank_[static_cast<size_t>(k)]] = v[rank_[static_cast<size_t>(k)]];
      const Eigen::VectorXd sym = w.head(symmetric_);
      Eigen::MatrixXd c = s_.isotropic ? coefficients_from_ibsss(s_.order, sym) : coefficients_from_bsss(sym);
      if (anti_) {
        const Eigen::VectorXd z = w.tail(total() - symmetric_);
        c += s_.isotropic ? coefficients_from_isotropic_antisymmetric(s_.order, z) : coefficients_from_antisymmetric(s_.order, z);
      }
      out.push_back(std::move(c));
    }
    return out;
  }

 private:
  const Spectrum& s_;
  bool anti_;
  Eigen::Index symmetric_ = 0;
  std::vector<Eigen::VectorXd> v_;
  std::vector<Eigen::Index> rank_;
};

}  // namespace

bool has_antisymmetric_terms(const Spectrum& s) {
  for (const auto& c : s.channels)
    if (c.rows() == c.cols() && (c - c.transpose()).cwiseAbs().maxCoeff() > 0.0) return true;
  return false;
}

int coefficient_total(const Spectrum& s) {
  long long n = s.isotropic ? isotropic_mode_count(s.order) : helmholtz_mode_count(s.order);
  if (has_antisymmetric_terms(s)) n += s.isotropic ? isotropic_antisymmetric_mode_count(s.order) : antisymmetric_mode_count(s.order);
  return static_cast<int>(n);
}

PruneResult prune_coefficients(Spectrum& s, const HeldOutErrors& errors, double target) {
  const RankedCoefficients ranked(s);
  Eigen::Index lo = 0, hi = ranked.total();
  while (lo < hi) {
    const Eigen::Index mid = (lo + hi) / 2;
    if (errors(ranked.with_kept(mid), s.order).l2 <= target) hi = mid;
    else lo = mid + 1;
  }
  auto pruned = ranked.with_kept(hi);
  PruneResult r;
  r.error = errors(pruned, s.order);
  r.total = static_cast<int>(ranked.total());
  r.pruned = r.error.l2 <= target;
  r.kept = r.pruned ? static_cast<int>(hi) : r.total;
  if (r.pruned) s.channels = std::move(pruned);
  return r;
}

PruneResult keep_largest(Spectrum& s, const HeldOutErrors& errors, int kept) {
  const RankedCoefficients ranked(s);
  PruneResult r;
  r.total = static_cast<int>(ranked.total());
  r.kept = std::min(std::max(kept, 0), r.total);
  r.pruned = r.kept < r.total;
  if (r.pruned) s.channels = ranked.with_kept(r.kept);
  r.error = errors(s.channels, s.order);
  return r;
}

}  // namespace icobrdf
