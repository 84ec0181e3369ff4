#include "core/sample_fit.hpp"

#include <Eigen/Householder>
#include <Eigen/QR>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.hpp"
#include "core/helmholtz_modes.hpp"
#include "core/hemisphere_basis.hpp"
#include "core/isotropic_modes.hpp"

namespace icobrdf {

namespace {

int unknown_count(int order, bool isotropic) {
  return isotropic ? isotropic_mode_count(order) : static_cast<int>(helmholtz_mode_count(order));
}

Eigen::MatrixXd modes_at(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  return isotropic ? isotropic_modes_eval(order, wi, wr) : helmholtz_modes_eval(order, wi, wr);
}

// Rows per chunk: keeps the chunk's design block near 4 million doubles (32 MB).
Eigen::Index chunk_rows(int unknowns) { return std::max<Eigen::Index>(64, 4'000'000 / std::max(unknowns, 1)); }

}  // namespace

Eigen::VectorXd tikhonov_penalties(int order, bool isotropic, double power) {
  if (!(power >= 0.0) || !std::isfinite(power))
    throw ArgumentError("Tikhonov penalties: power p must be finite and >= 0, got " + std::to_string(power));
  std::vector<std::pair<int, int>> nm;
  if (isotropic) {
    for (const auto& k : isotropic_modes(order)) nm.emplace_back(k.n, k.m);
  } else {
    for (const auto& k : helmholtz_modes(order)) nm.emplace_back(k.n, k.m);
  }
  Eigen::VectorXd d(static_cast<Eigen::Index>(nm.size()));
  for (size_t k = 0; k < nm.size(); ++k) {
    const double e = nm[k].first * (nm[k].first + 2.0) + nm[k].second * (nm[k].second + 2.0);
    d[static_cast<Eigen::Index>(k)] = std::pow(e, power);  // pow(0, 0) = 1: plain ridge for p = 0
  }
  return d;
}

SampleFitAccumulator::SampleFitAccumulator(const SampleFitOptions& options, int channels)
    : options_(options), channels_(channels) {
  const int max_order = options.isotropic ? 128 : kMaxSampleFitOrder;
  if (options.order < 0 || options.order > max_order)
    throw ArgumentError("sample fit: order must be in [0, " + std::to_string(max_order) + "] for " +
                        (options.isotropic ? "isotropic" : "general") + " modes, got " + std::to_string(options.order));
  if (channels < 1) throw ArgumentError("sample fit: channels must be >= 1, got " + std::to_string(channels));
  if (!(options.tikhonov >= 0.0) || !std::isfinite(options.tikhonov))
    throw ArgumentError("sample fit: Tikhonov lambda must be finite and >= 0, got " + std::to_string(options.tikhonov));
  if (!(options.tikhonov_power >= 0.0) || !std::isfinite(options.tikhonov_power))
    throw ArgumentError("sample fit: Tikhonov power p must be finite and >= 0, got " +
                        std::to_string(options.tikhonov_power));
  if (!std::isfinite(options.rank_tolerance) || options.rank_tolerance >= 1.0)
    throw ArgumentError("sample fit: rank tolerance must be < 1 (negative for the default), got " +
                        std::to_string(options.rank_tolerance));
  unknowns_ = unknown_count(options.order, options.isotropic);
  r_ = Eigen::MatrixXd::Zero(unknowns_ + channels_, unknowns_ + channels_);
}

void SampleFitAccumulator::absorb(const Eigen::MatrixXd& block) {
  const Eigen::Index k = r_.cols();
  Eigen::MatrixXd stacked(k + block.rows(), k);
  stacked.topRows(k) = r_;
  stacked.bottomRows(block.rows()) = block;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(stacked);
  r_ = qr.matrixQR().topRows(k).triangularView<Eigen::Upper>();
}

void SampleFitAccumulator::add(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                               const Eigen::VectorXd& weights) {
  const Eigen::Index s = wi.rows();
  if (wr.rows() != s || values.rows() != s || weights.size() != s || values.cols() != channels_)
    throw ArgumentError("sample fit: expected wi, wr (rows x 3), values (rows x " + std::to_string(channels_) +
                        ") and weights (rows) with equal rows; got " + std::to_string(wi.rows()) + ", " +
                        std::to_string(wr.rows()) + ", " + std::to_string(values.rows()) + " x " +
                        std::to_string(values.cols()) + ", " + std::to_string(weights.size()));
  for (Eigen::Index i = 0; i < s; ++i) {
    if (!std::isfinite(weights[i]) || weights[i] < 0.0)
      throw ArgumentError("sample fit: weight of sample " + std::to_string(i) + " must be finite and >= 0, got " +
                          std::to_string(weights[i]));
    if (!values.row(i).allFinite())
      throw ArgumentError("sample fit: value of sample " + std::to_string(i) + " is not finite");
  }
  const Eigen::Index step = chunk_rows(unknowns_);
  for (Eigen::Index b = 0; b < s; b += step) {
    const Eigen::Index e = std::min(s, b + step);
    std::vector<Eigen::Index> keep;
    for (Eigen::Index i = b; i < e; ++i)
      if (weights[i] > 0.0) keep.push_back(i);
    if (keep.empty()) continue;
    const auto n = static_cast<Eigen::Index>(keep.size());
    RowMatrix3d a(n, 3), c(n, 3);
    Eigen::VectorXd sw(n);
    Eigen::MatrixXd y(n, channels_);
    for (Eigen::Index t = 0; t < n; ++t) {
      a.row(t) = wi.row(keep[static_cast<size_t>(t)]);
      c.row(t) = wr.row(keep[static_cast<size_t>(t)]);
      sw[t] = std::sqrt(weights[keep[static_cast<size_t>(t)]]);
      y.row(t) = values.row(keep[static_cast<size_t>(t)]);
      weight_sum_ += weights[keep[static_cast<size_t>(t)]];
    }
    Eigen::MatrixXd block(n, unknowns_ + channels_);
    block.leftCols(unknowns_) = sw.asDiagonal() * modes_at(options_.order, options_.isotropic, a, c);
    block.rightCols(channels_) = sw.asDiagonal() * y;
    absorb(block);
    samples_ += n;
  }
}

SampleFitResult SampleFitAccumulator::solve() const {
  if (samples_ == 0) throw ArgumentError("sample fit: no sample with positive weight");
  const int k = unknowns_;
  const Eigen::MatrixXd r11 = r_.topLeftCorner(k, k);
  const Eigen::MatrixXd z = r_.topRightCorner(k, channels_);
  const Eigen::MatrixXd r22 = r_.bottomRightCorner(channels_, channels_);

  SampleFitResult out;
  out.order = options_.order;
  out.isotropic = options_.isotropic;
  out.samples = samples_;
  out.unknowns = k;
  const double eps = std::numeric_limits<double>::epsilon();
  out.rank_tolerance = options_.rank_tolerance >= 0.0
                           ? options_.rank_tolerance
                           : static_cast<double>(std::max<long long>(samples_, k)) * eps;

  // The largest singular value of W^(1/2) A (all columns) sets the scale of every threshold.
  Eigen::BDCSVD<Eigen::MatrixXd> full(r11);
  const double s1 = full.singularValues().size() ? full.singularValues()[0] : 0.0;
  out.rank_threshold = out.rank_tolerance * s1;

  // Unseen modes: zero columns (column norms of R11 equal those of W^(1/2) A).
  out.unseen.assign(static_cast<size_t>(k), false);
  std::vector<int> seen;
  for (int j = 0; j < k; ++j) {
    if (r11.col(j).norm() <= out.rank_threshold || s1 == 0.0) {
      out.unseen[static_cast<size_t>(j)] = true;
      ++out.unseen_modes;
    } else {
      seen.push_back(j);
    }
  }
  const auto ks = static_cast<Eigen::Index>(seen.size());
  Eigen::MatrixXd rs(k, ks);
  for (Eigen::Index t = 0; t < ks; ++t) rs.col(t) = r11.col(seen[static_cast<size_t>(t)]);

  Eigen::MatrixXd xs = Eigen::MatrixXd::Zero(ks, channels_);
  if (ks > 0) {
    Eigen::BDCSVD<Eigen::MatrixXd> svd(rs, Eigen::ComputeThinU | Eigen::ComputeThinV);
    out.singular_values = svd.singularValues();
    out.effective_rank = 0;
    for (Eigen::Index t = 0; t < out.singular_values.size(); ++t)
      if (out.singular_values[t] > out.rank_threshold) ++out.effective_rank;
    if (options_.tikhonov == 0.0) {
      const int r = out.effective_rank;
      const Eigen::MatrixXd ut = svd.matrixU().leftCols(r).transpose() * z;
      xs = svd.matrixV().leftCols(r) * (out.singular_values.head(r).cwiseInverse().asDiagonal() * ut);
    } else {
      const Eigen::VectorXd d = tikhonov_penalties(options_.order, options_.isotropic, options_.tikhonov_power);
      Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(k + ks, ks);
      aug.topRows(k) = rs;
      for (Eigen::Index t = 0; t < ks; ++t) aug(k + t, t) = std::sqrt(options_.tikhonov * d[seen[static_cast<size_t>(t)]]);
      Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(k + ks, channels_);
      rhs.topRows(k) = z;
      Eigen::BDCSVD<Eigen::MatrixXd> reg(aug, Eigen::ComputeThinU | Eigen::ComputeThinV);
      const Eigen::VectorXd sv = reg.singularValues();
      const double thr = out.rank_tolerance * (sv.size() ? sv[0] : 0.0);
      int r = 0;
      while (r < sv.size() && sv[r] > thr) ++r;
      const Eigen::MatrixXd ut = reg.matrixU().leftCols(r).transpose() * rhs;
      xs = reg.matrixV().leftCols(r) * (sv.head(r).cwiseInverse().asDiagonal() * ut);
    }
  }
  out.null_space_dimension = k - out.effective_rank;
  out.modes = Eigen::MatrixXd::Zero(k, channels_);
  for (Eigen::Index t = 0; t < ks; ++t) out.modes.row(seen[static_cast<size_t>(t)]) = xs.row(t);

  // Weighted residual: ||W^(1/2)(A x - y)||^2 = ||R11 x - z||^2 + ||R22 e_c||^2.
  out.residual_rms.resize(channels_);
  for (int c = 0; c < channels_; ++c) {
    const double fit_part = (r11 * out.modes.col(c) - z.col(c)).squaredNorm();
    const double rest = r22.col(c).squaredNorm();
    out.residual_rms[c] = std::sqrt((fit_part + rest) / weight_sum_);
  }
  for (int c = 0; c < channels_; ++c)
    out.channels.push_back(options_.isotropic ? coefficients_from_ibsss(options_.order, out.modes.col(c))
                                              : coefficients_from_bsss(out.modes.col(c)));
  return out;
}

SampleFitResult fit_samples(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                            const Eigen::VectorXd& weights, const SampleFitOptions& options) {
  SampleFitAccumulator acc(options, static_cast<int>(values.cols()));
  acc.add(wi, wr, values, weights.size() == 0 ? Eigen::VectorXd::Ones(wi.rows()).eval() : weights);
  return acc.solve();
}

}  // namespace icobrdf
