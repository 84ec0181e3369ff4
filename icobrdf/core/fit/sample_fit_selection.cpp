#include "icobrdf/core/fit/sample_fit_selection.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <iterator>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/support/scramble.hpp"

namespace icobrdf {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string fmt_g(double x, int digits = 3) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, x);
  return buf;
}

int max_order_of(bool isotropic) { return isotropic ? 128 : kMaxSampleFitOrder; }

// The normal equations of one fold, for the modes of order `order`, and their sum.
struct Folds {
  int order = -1;
  bool isotropic = false;
  std::vector<NormalEquations> fold;
  NormalEquations total;
  const DenseKernels* kernels = nullptr;  // of the training factorizations (Eigen's when null)
  // The samples (they outlive the folds) and each row's fold (-1: weight 0), for the held-out passes that
  // single-precision Gram products need.
  const RowMatrix3d* wi = nullptr;
  const RowMatrix3d* wr = nullptr;
  const Eigen::MatrixXd* values = nullptr;
  const Eigen::VectorXd* weights = nullptr;
  std::vector<int> fold_of_row;
  // A fit split over processes (SampleFitSplit): the folds hold the sums over every process's rows, and
  // fold_of_row lists this process's rows only (the others -1).
  std::shared_ptr<const SampleFitSplit> split;
};

Folds assemble_folds(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                     const Eigen::VectorXd& weights, int folds, const FitProgress& progress, const DenseKernels* kernels,
                     bool single_products = false, const std::shared_ptr<const SampleFitSplit>& split = nullptr) {
  require_sample_fit_memory(order, isotropic, folds);  // before the folds' Grams (5 of them at k^2 doubles each)
  std::vector<std::vector<Eigen::Index>> rows(static_cast<size_t>(folds));
  Folds f;
  f.split = split;
  f.fold_of_row.assign(static_cast<size_t>(weights.size()), -1);
  // This process's share of the rows of positive weight: [first, last) of them (SampleFitSplit).
  long long first = 0, last = std::numeric_limits<long long>::max();
  if (splits_work(split)) std::tie(first, last) = split->rows_of_part(static_cast<long long>((weights.array() > 0.0).count()));
  long long index = 0;
  for (Eigen::Index i = 0; i < weights.size(); ++i)
    if (weights[i] > 0.0) {
      const long long at = index++;
      if (at < first || at >= last) continue;
      const int k = cross_validation_fold(at, folds);
      rows[static_cast<size_t>(k)].push_back(i);
      f.fold_of_row[static_cast<size_t>(i)] = k;
    }
  f.wi = &wi;
  f.wr = &wr;
  f.values = &values;
  f.weights = &weights;
  f.order = order;
  f.isotropic = isotropic;
  f.kernels = kernels;
  for (int k = 0; k < folds; ++k) {
    FitProgress p;
    if (progress)
      p = [&progress, k, folds](const char*, double x) { progress("assembling the folds", (k + x) / folds); };
    if (rows[static_cast<size_t>(k)].empty()) {
      // An empty fold: zero normal equations (the fold then has no held-out error).
      const int u = sample_fit_unknowns(order, isotropic);
      NormalEquations z;
      z.gram = Eigen::MatrixXd::Zero(u, u);
      z.rhs = Eigen::MatrixXd::Zero(u, values.cols());
      z.yy = Eigen::VectorXd::Zero(values.cols());
      z.single_products = single_products;
      f.fold.push_back(std::move(z));
      continue;
    }
    f.fold.push_back(
        assemble_normal_equations(order, isotropic, wi, wr, values, weights, rows[static_cast<size_t>(k)], p, kernels, single_products));
  }
  sum_normal_equations(split, f.fold);  // every process's rows: one sum of every fold's normal equations
  f.total = f.fold[0];
  for (int k = 1; k < folds; ++k) {
    f.total.gram += f.fold[static_cast<size_t>(k)].gram;
    f.total.rhs += f.fold[static_cast<size_t>(k)].rhs;
    f.total.yy += f.fold[static_cast<size_t>(k)].yy;
    f.total.weight_sum += f.fold[static_cast<size_t>(k)].weight_sum;
    f.total.samples += f.fold[static_cast<size_t>(k)].samples;
  }
  return f;
}

// The leading block of the normal equations: the modes of a lower order (prefix of the library order).
NormalEquations leading(const NormalEquations& ne, int unknowns) {
  NormalEquations out;
  out.gram = ne.gram.topLeftCorner(unknowns, unknowns);
  out.rhs = ne.rhs.topRows(unknowns);
  out.yy = ne.yy;
  out.weight_sum = ne.weight_sum;
  out.samples = ne.samples;
  out.single_products = ne.single_products;
  return out;
}

struct OrderScore {
  bool determined = false;
  double mse = kNaN;     // weighted mean square over all held-out samples and channels
  double mse_se = kNaN;  // standard error over folds
};

// Below this many entries of a fold's factor its correction solves run on one thread (a parallel region costs more).
constexpr double kParallelFoldSolveMinEntries = 1e5;

// Below this many multiply-adds (a fold's Cholesky factorization, unknowns^3 / 3) the folds are factored one
// after the other: a parallel region costs more than it saves.
constexpr double kParallelFoldMinWork = 5e7;

// The folds' training factorizations and held-out sums of squares for `order` and lambda `tikhonov` (power
// `power`): run(i) for each fold on any thread (one thread each), then score() sums them in fold order,
// whatever ran where.
class FoldScoring {
 public:
  FoldScoring(const Folds& f, int order, double tikhonov, double power)
      : f_(f), order_(order), k_(sample_fit_unknowns(order, f.isotropic)), d_(Eigen::VectorXd::Zero(k_)),
        sse_(f.fold.size(), 0.0), failed_(f.fold.size(), 0), single_llt_(f.fold.size()), double_llt_(f.fold.size()), x_(f.fold.size()),
        cond_(f.fold.size(), 0.0) {
    if (tikhonov > 0.0) d_ = tikhonov * tikhonov_penalties(order, f.isotropic, power);
  }
  int folds() const { return static_cast<int>(f_.fold.size()); }
  int unknowns() const { return k_; }

  void run(int i) {
    const NormalEquations& hold = f_.fold[static_cast<size_t>(i)];
    if (hold.samples == 0) return;
    const double max_cond_g = kMaxDeterminedCondition * kMaxDeterminedCondition;
    Eigen::MatrixXd gt = training_gram(i);
    if (f_.total.single_products) {  // a single-precision factor, refined and scored from the samples by refine_single()
      Eigen::LLT<Eigen::MatrixXf> llt = cholesky(Eigen::MatrixXf(gt.cast<float>()));
      if (llt.info() != Eigen::Success || !(static_cast<double>(llt.rcond()) * max_cond_g >= 1.0)) {
        failed_[static_cast<size_t>(i)] = 1;
        return;
      }
      x_[static_cast<size_t>(i)] = llt.solve(training_rhs(i).cast<float>()).cast<double>();
      cond_[static_cast<size_t>(i)] = 1.0 / std::sqrt(std::max(static_cast<double>(llt.rcond()), std::numeric_limits<double>::min()));
      single_llt_[static_cast<size_t>(i)] = std::move(llt);
      return;
    }
    Eigen::LLT<Eigen::MatrixXd> llt = cholesky(f_.kernels, std::move(gt));
    if (llt.info() != Eigen::Success || !(llt.rcond() * max_cond_g >= 1.0)) {  // undetermined
      failed_[static_cast<size_t>(i)] = 1;
      return;
    }
    const Eigen::MatrixXd x = llt.solve(training_rhs(i));
    const Eigen::MatrixXd gx = hold.gram.topLeftCorner(k_, k_) * x;
    double sse = 0.0;
    for (Eigen::Index c = 0; c < x.cols(); ++c)
      sse += std::max(0.0, hold.yy[c] - 2.0 * x.col(c).dot(hold.rhs.col(c).head(k_)) + x.col(c).dot(gx.col(c)));
    sse_[static_cast<size_t>(i)] = sse;
  }

  // With single-precision Gram products the folds' Gram matrices carry a rounding of ~1e-6 relative, which the
  // expanded held-out error y_f^T W y_f - 2 x^T b_f + x^T G_f x would amplify by y^T W y / SSE (a low-noise fit's
  // CV error would be lost in it), and the training solutions (from single-precision factors, run()) by cond(G).
  // So, after run() of every fold: passes over the samples refine each fold's solution (as sample_fit.hpp refines
  // the fit, refinement_converged) and the held-out errors come from the samples themselves (held_out_pass). A
  // fold still refining after kMaxRefinementPasses is factored again in double and refined again; one that does
  // not converge then either is marked failed (the CV error is then NaN).
  void refine_single() {
    if (!f_.total.single_products) return;
    std::vector<int> active;
    for (int i = 0; i < folds(); ++i)
      if (f_.fold[static_cast<size_t>(i)].samples > 0 && !failed_[static_cast<size_t>(i)]) active.push_back(i);
    if (active.empty()) return;
    const auto n = static_cast<size_t>(folds());
    std::vector<Eigen::MatrixXd> x(n, Eigen::MatrixXd::Zero(k_, f_.total.rhs.cols()));
    for (int i : active) x[static_cast<size_t>(i)] = x_[static_cast<size_t>(i)];
    std::vector<char> done(n, 0);
    std::vector<double> previous(n, 0.0);  // each fold's last correction (largest entry)
    std::vector<int> passes(n, 0);         // with its current factor
    std::vector<Eigen::MatrixXd> dx(n);
    for (;;) {
      HeldOutPass h = held_out_pass(order_, f_.isotropic, *f_.wi, *f_.wr, *f_.values, *f_.weights, f_.fold_of_row, x);
      if (splits_work(f_.split)) {  // this process's rows -> every process's
        std::vector<Eigen::MatrixXd> m(std::make_move_iterator(h.c.begin()), std::make_move_iterator(h.c.end()));
        for (const Eigen::VectorXd& v : h.held) m.push_back(v);
        f_.split->sum(m);
        for (size_t u = 0; u < n; ++u) {
          h.c[u] = std::move(m[u]);
          h.held[u] = m[n + u].col(0);
        }
      }
      // The folds' corrections are independent (two triangular solves each, bound by memory): one thread each.
#pragma omp parallel for schedule(dynamic, 1) if (static_cast<double>(k_) * k_ >= kParallelFoldSolveMinEntries)
      for (size_t a = 0; a < active.size(); ++a) {
        const auto u = static_cast<size_t>(active[a]);
        if (done[u]) continue;
        const Eigen::MatrixXd r = h.c[u] - d_.asDiagonal() * x[u];
        dx[u] = double_llt_[u] ? double_llt_[u]->solve(r) : Eigen::MatrixXd(single_llt_[u]->solve(r.cast<float>()).cast<double>());
      }
      bool all = true;
      for (int i : active) {
        const auto u = static_cast<size_t>(i);
        sse_[u] = h.held[u].sum();
        if (done[u]) continue;
        x[u] += dx[u];
        ++passes[u];
        const double last = dx[u].cwiseAbs().maxCoeff();
        if (dx[u].allFinite() && refinement_converged(previous[u], last, x[u].cwiseAbs().maxCoeff(), kRefinementFloor * cond_[u])) {
          done[u] = 1;
          continue;
        }
        previous[u] = last;
        all = false;
        if (passes[u] < kMaxRefinementPasses && dx[u].allFinite()) continue;
        if (double_llt_[u]) {  // a double factor did not converge either
          failed_[u] = 1;
          done[u] = 1;
          continue;
        }
        double_llt_[u] = cholesky(f_.kernels, training_gram(i));
        if (double_llt_[u]->info() != Eigen::Success) {
          failed_[u] = 1;
          done[u] = 1;
          continue;
        }
        x[u] = double_llt_[u]->solve(training_rhs(i));
        previous[u] = 0.0;
        passes[u] = 0;
      }
      if (all) return;
    }
  }

  OrderScore score() const {
    OrderScore s;
    const auto channels = f_.total.rhs.cols();
    double sse_total = 0.0, w_total = 0.0;
    std::vector<double> fold_mse;
    for (int i = 0; i < folds(); ++i) {
      const NormalEquations& hold = f_.fold[static_cast<size_t>(i)];
      if (hold.samples == 0) continue;
      if (failed_[static_cast<size_t>(i)]) return s;
      sse_total += sse_[static_cast<size_t>(i)];
      w_total += hold.weight_sum * static_cast<double>(channels);
      fold_mse.push_back(sse_[static_cast<size_t>(i)] / (hold.weight_sum * static_cast<double>(channels)));
    }
    if (fold_mse.empty() || !(w_total > 0.0)) return s;
    s.determined = true;
    s.mse = sse_total / w_total;
    double mean = 0.0, var = 0.0;
    for (double m : fold_mse) mean += m;
    mean /= static_cast<double>(fold_mse.size());
    for (double m : fold_mse) var += (m - mean) * (m - mean);
    const double n = static_cast<double>(fold_mse.size());
    s.mse_se = n > 1 ? std::sqrt(var / (n - 1) / n) : 0.0;
    return s;
  }

 private:
  // The training problem of fold i (all folds but i) at this order: G - G_i + lambda D, and b - b_i.
  Eigen::MatrixXd training_gram(int i) const {
    Eigen::MatrixXd gt = f_.total.gram.topLeftCorner(k_, k_) - f_.fold[static_cast<size_t>(i)].gram.topLeftCorner(k_, k_);
    gt.diagonal() += d_;
    return gt;
  }
  Eigen::MatrixXd training_rhs(int i) const {
    return f_.total.rhs.topRows(k_) - f_.fold[static_cast<size_t>(i)].rhs.topRows(k_);
  }

  const Folds& f_;
  int order_;
  int k_;
  Eigen::VectorXd d_;
  std::vector<double> sse_;
  std::vector<char> failed_;
  // Single products: each fold's training factor (single precision; double after a failed refinement), its
  // unrefined solution and its condition estimate.
  std::vector<std::optional<Eigen::LLT<Eigen::MatrixXf>>> single_llt_;
  std::vector<std::optional<Eigen::LLT<Eigen::MatrixXd>>> double_llt_;
  std::vector<Eigen::MatrixXd> x_;
  std::vector<double> cond_;
};

OrderScore score_order(const Folds& f, int order, double tikhonov, double power) {
  FoldScoring scoring(f, order, tikhonov, power);
  const int k = scoring.unknowns(), folds = scoring.folds();
  // The folds' training factorizations are independent: one thread each (a thread per fold when the
  // factorization is worth a parallel region and the kernels are not threaded themselves).
  const bool parallel = static_cast<double>(k) * k * k / 3.0 >= kParallelFoldMinWork && !(f.kernels && f.kernels->threaded);
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, std::min(folds, omp_get_max_threads()))) if (parallel)
  for (int i = 0; i < folds; ++i) scoring.run(i);
  scoring.refine_single();
  return scoring.score();
}

OrderCrossValidation score_orders(const Folds& f, int min_order, int max_order, double tikhonov, double power,
                                  const FitProgress& progress) {
  OrderCrossValidation cv;
  cv.folds = static_cast<int>(f.fold.size());
  const double data_ms = f.total.yy.sum() / (f.total.weight_sum * static_cast<double>(f.total.yy.size()));
  std::vector<OrderScore> scores;
  for (int n = min_order; n <= max_order; ++n) {
    if (progress) progress("cross-validating the order", static_cast<double>(n - min_order) / (max_order - min_order + 1));
    const OrderScore s = score_order(f, n, tikhonov, power);
    cv.orders.push_back(n);
    cv.determined.push_back(s.determined);
    cv.rms.push_back(s.determined ? std::sqrt(s.mse) : kNaN);
    // delta method: se(sqrt(m)) = se(m) / (2 sqrt(m))
    cv.rms_se.push_back(s.determined && s.mse > 0.0 ? s.mse_se / (2.0 * std::sqrt(s.mse)) : (s.determined ? 0.0 : kNaN));
    scores.push_back(s);
  }
  int best = -1;
  for (size_t i = 0; i < scores.size(); ++i)
    if (scores[i].determined && (best < 0 || scores[i].mse < scores[static_cast<size_t>(best)].mse)) best = static_cast<int>(i);
  if (best < 0) return cv;
  // The lowest order within kCvTieFraction of the best mean square (or its resolution).
  const double threshold = scores[static_cast<size_t>(best)].mse * (1.0 + kCvTieFraction) + kCvResolution * data_ms;
  for (size_t i = 0; i < scores.size(); ++i)
    if (scores[i].determined && scores[i].mse <= threshold) {
      cv.chosen = cv.orders[i];
      break;
    }
  return cv;
}

// The (class, order) of the joint choice (header: "Model class"): the fewest unknowns among the determined
// candidates of both classes within kCvTieFraction of the smallest CV mean square; the isotropic modes on a tie.
// Returns {isotropic, order}; order -1 when no candidate is determined.
std::pair<bool, int> choose_class_and_order(const OrderCrossValidation& iso, const OrderCrossValidation& gen, double data_ms) {
  double best = std::numeric_limits<double>::infinity();
  for (const OrderCrossValidation* cv : {&iso, &gen})
    for (size_t i = 0; i < cv->orders.size(); ++i)
      if (cv->determined[i]) best = std::min(best, cv->rms[i] * cv->rms[i]);
  if (!std::isfinite(best)) return {true, -1};
  const double threshold = best * (1.0 + kCvTieFraction) + kCvResolution * data_ms;
  std::pair<bool, int> chosen{true, -1};
  int fewest = std::numeric_limits<int>::max();
  for (const bool isotropic : {true, false}) {
    const OrderCrossValidation& cv = isotropic ? iso : gen;
    for (size_t i = 0; i < cv.orders.size(); ++i) {
      if (!cv.determined[i] || !(cv.rms[i] * cv.rms[i] <= threshold)) continue;
      const int k = sample_fit_unknowns(cv.orders[i], isotropic);
      if (k < fewest) {
        fewest = k;
        chosen = {isotropic, cv.orders[i]};
      }
    }
  }
  return chosen;
}

// The CV RMS of a class's own choice (NaN when it has none).
double chosen_rms(const OrderCrossValidation& cv) {
  for (size_t i = 0; i < cv.orders.size(); ++i)
    if (cv.orders[i] == cv.chosen) return cv.rms[i];
  return kNaN;
}

bool determined(const SampleFitResult& r) {
  if (r.unseen_modes > 0) return false;
  if (r.tikhonov > 0.0) return true;
  return r.null_space_dimension == 0 && r.condition <= kMaxDeterminedCondition;
}

std::string determinacy_text(const SampleFitResult& r) {
  std::string t = "rank " + std::to_string(r.effective_rank) + " of " + std::to_string(r.unknowns);
  if (r.unseen_modes > 0) t += ", " + std::to_string(r.unseen_modes) + " unseen";
  if (r.effective_rank > 0) t += ", condition " + fmt_g(r.condition);
  return t;
}

std::string modes_name(bool isotropic) { return isotropic ? "isotropic modes" : "general modes"; }

// Directions of a Fibonacci lattice of the hemisphere (equal-area in z), n of them.
RowMatrix3d hemisphere_lattice(int n) {
  RowMatrix3d d(n, 3);
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (i + 0.5) / n, r = std::sqrt(std::max(0.0, 1.0 - z * z)), phi = golden * i;
    d.row(i) << r * std::cos(phi), r * std::sin(phi), z;
  }
  return d;
}

double max_abs_over_domain(const SampleFitResult& r) {
  const int n = kScaleCheckDirections;
  const RowMatrix3d lat = hemisphere_lattice(n);
  RowMatrix3d wi(n * n, 3), wr(n * n, 3);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      wi.row(a * n + b) = lat.row(a);
      wr.row(a * n + b) = lat.row(b);
    }
  return (sample_fit_modes(r.order, r.isotropic, wi, wr) * r.modes).cwiseAbs().maxCoeff();
}

}  // namespace

int cross_validation_fold(long long index, int folds) {
  return static_cast<int>(splitmix64(static_cast<std::uint64_t>(index)) % static_cast<std::uint64_t>(folds));
}

OrderCrossValidation cross_validate_order(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                                          const Eigen::VectorXd& weights, bool isotropic, int min_order, int max_order,
                                          double tikhonov, double tikhonov_power, int folds, const FitProgress& progress) {
  if (min_order < 0 || max_order < min_order || max_order > max_order_of(isotropic))
    throw ArgumentError("cross-validation: orders " + std::to_string(min_order) + ".." + std::to_string(max_order) +
                        " are not a range within [0, " + std::to_string(max_order_of(isotropic)) + "]");
  if (folds < 2) throw ArgumentError("cross-validation: at least 2 folds are needed, got " + std::to_string(folds));
  SampleFitOptions o;
  o.order = max_order;
  o.isotropic = isotropic;
  o.tikhonov = tikhonov;
  o.tikhonov_power = tikhonov_power;
  const Eigen::VectorXd w = weights.size() == 0 ? Eigen::VectorXd::Ones(wi.rows()).eval() : weights;
  check_sample_fit_input(o, wi, wr, values, w);
  const Folds f = assemble_folds(max_order, isotropic, wi, wr, values, w, folds, progress, nullptr);
  return score_orders(f, min_order, max_order, tikhonov, tikhonov_power, progress);
}

GcvChoice choose_tikhonov_gcv(const NormalEquations& ne, int order, bool isotropic, double tikhonov_power) {
  const Eigen::VectorXd d = tikhonov_penalties(order, isotropic, tikhonov_power);
  const Eigen::Index k = d.size();
  if (ne.gram.rows() != k) throw ArgumentError("GCV: the normal equations do not match the modes");
  const double max_diag = ne.gram.diagonal().maxCoeff();
  std::vector<Eigen::Index> un, pen;  // seen modes, unpenalized and penalized
  for (Eigen::Index j = 0; j < k; ++j) {
    if (!(ne.gram(j, j) > max_diag * static_cast<double>(k) * std::numeric_limits<double>::epsilon())) continue;  // unseen
    (d[j] == 0.0 ? un : pen).push_back(j);
  }
  const auto nu = static_cast<Eigen::Index>(un.size()), np = static_cast<Eigen::Index>(pen.size());
  // Nothing penalized is seen (e.g. a handful of samples): no lambda to choose. Returned before the solves below,
  // whose right-hand sides would have no columns (an LDLT solve of a 0-column block reads through a null pointer).
  if (np == 0) return GcvChoice{};
  const auto channels = ne.rhs.cols();
  Eigen::MatrixXd gnn(nu, nu), gnp(nu, np), gpp(np, np), bn(nu, channels), bp(np, channels);
  for (Eigen::Index a = 0; a < nu; ++a) {
    for (Eigen::Index b = 0; b < nu; ++b) gnn(a, b) = ne.gram(un[a], un[b]);
    for (Eigen::Index b = 0; b < np; ++b) gnp(a, b) = ne.gram(un[a], pen[b]);
    bn.row(a) = ne.rhs.row(un[a]);
  }
  for (Eigen::Index a = 0; a < np; ++a) {
    for (Eigen::Index b = 0; b < np; ++b) gpp(a, b) = ne.gram(pen[a], pen[b]);
    bp.row(a) = ne.rhs.row(pen[a]);
  }
  Eigen::VectorXd yy = ne.yy;
  Eigen::MatrixXd s = gpp, c = bp;
  if (nu > 0) {
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(gnn);
    s -= gnp.transpose() * ldlt.solve(gnp);
    c -= gnp.transpose() * ldlt.solve(bn);
    const Eigen::MatrixXd xn = ldlt.solve(bn);
    for (Eigen::Index ch = 0; ch < channels; ++ch) yy[ch] -= bn.col(ch).dot(xn.col(ch));
  }
  Eigen::VectorXd dh(np);
  for (Eigen::Index a = 0; a < np; ++a) dh[a] = 1.0 / std::sqrt(d[pen[a]]);
  s = dh.asDiagonal() * s * dh.asDiagonal();
  c = dh.asDiagonal() * c;
  GcvChoice g;
  const double n = static_cast<double>(ne.samples);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(s);
  const Eigen::VectorXd mu = es.eigenvalues().cwiseMax(0.0);
  const Eigen::MatrixXd chat2 = (es.eigenvectors().transpose() * c).array().square().matrix();
  const double mu_max = mu.maxCoeff();
  if (!(mu_max > 0.0)) return g;
  g.score = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kGcvPoints; ++i) {
    const double lambda = mu_max * std::pow(10.0, -14.0 + 16.0 * i / (kGcvPoints - 1));
    double rss = 0.0, trh = static_cast<double>(nu);
    for (Eigen::Index j = 0; j < np; ++j) trh += mu[j] / (mu[j] + lambda);
    for (Eigen::Index ch = 0; ch < channels; ++ch) {
      double fitted = 0.0;
      for (Eigen::Index j = 0; j < np; ++j) fitted += chat2(j, ch) * (mu[j] + 2.0 * lambda) / ((mu[j] + lambda) * (mu[j] + lambda));
      rss += std::max(0.0, yy[ch] - fitted);
    }
    if (!(n - trh > 0.0)) continue;
    const double score = n * rss / ((n - trh) * (n - trh));
    g.lambdas.push_back(lambda);
    g.scores.push_back(score);
    if (score < g.score) {
      g.score = score;
      g.lambda = lambda;
    }
  }
  return g;
}

// Long function: the numbered steps (order, lambda, fit with its fallbacks, scale check, CV error) run in
// order on one shared state (the options, the folds, the normal equations and the early CV scoring that each
// step refines), so they read best in one piece.
CheckedSampleFit fit_samples_checked(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                                     const Eigen::VectorXd& weights, const SampleFitPlan& plan) {
  const Eigen::VectorXd w = weights.size() == 0 ? Eigen::VectorXd::Ones(wi.rows()).eval() : weights;
  SampleFitOptions o = plan.options;
  if (plan.choose_order) o.order = 0;
  if (plan.choose_tikhonov) o.tikhonov = 0.0;
  check_sample_fit_input(o, wi, wr, values, w);
  if (plan.folds < 2) throw ArgumentError("sample fit: at least 2 cross-validation folds are needed, got " + std::to_string(plan.folds));
  CheckedSampleFit out;
  out.cv_folds = plan.folds;
  long long positive = 0;
  for (Eigen::Index i = 0; i < w.size(); ++i)
    if (w[i] > 0.0) {
      ++positive;
      out.max_abs_sample = std::max(out.max_abs_sample, values.row(i).cwiseAbs().maxCoeff());
    }
  if (positive == 0) throw ArgumentError("sample fit: no sample with positive weight");

  // 1. The order (and the class).
  Folds folds;
  if (plan.choose_order) {
    // The largest order with enough training samples per unknown.
    const auto top_order = [&](bool isotropic) {
      const int cap = plan.max_order >= 0 ? std::min(plan.max_order, max_order_of(isotropic))
                                          : (isotropic ? kMaxAutoOrderIsotropic : kMaxAutoOrderGeneral);
      const double training = static_cast<double>(positive) * (plan.folds - 1) / plan.folds;
      int top = 0;
      while (top < cap && sample_fit_unknowns(top + 1, isotropic) * kMinSamplesPerUnknown <= training) ++top;
      return top;
    };
    const auto score_class = [&](bool isotropic, Folds& f) {
      f = assemble_folds(top_order(isotropic), isotropic, wi, wr, values, w, plan.folds, o.progress, o.kernels, false, o.split);
      return score_orders(f, 0, f.order, o.tikhonov, o.tikhonov_power, o.progress);
    };
    if (plan.choose_class) {
      Folds general;
      out.isotropic_cv = score_class(true, folds);
      out.general_cv = score_class(false, general);
      out.cv_rms_isotropic = chosen_rms(out.isotropic_cv);
      out.cv_rms_general = chosen_rms(out.general_cv);
      const double data_ms = folds.total.yy.sum() / (folds.total.weight_sum * static_cast<double>(folds.total.yy.size()));
      const auto [isotropic, order] = choose_class_and_order(out.isotropic_cv, out.general_cv, data_ms);
      o.isotropic = isotropic;
      if (!isotropic) folds = std::move(general);
      out.order_cv = isotropic ? out.isotropic_cv : out.general_cv;
      out.order_cv.chosen = order;
      out.class_choice = "cross-validation";
    } else {
      out.order_cv = score_class(o.isotropic, folds);
    }
    const int top = folds.order;
    if (out.order_cv.chosen < 0) {
      // Too few samples for every fold to train even the constant: the isotropic order 0 (the weighted mean of
      // the samples, determined by any one of them) instead of a refusal.
      out.notes.push_back("the " + std::to_string(positive) + " samples determine no order of the " +
                          (plan.choose_class ? std::string("isotropic or general modes") : modes_name(o.isotropic)) +
                          " (0.." + std::to_string(top) + ") in every cross-validation fold: fitted the isotropic order 0 (their weighted mean)");
      o.isotropic = true;
      folds = assemble_folds(0, true, wi, wr, values, w, plan.folds, o.progress, o.kernels, false, o.split);
      out.order_cv.chosen = 0;
    }
    o.order = out.order_cv.chosen;
    out.order_choice = "cross-validation";
    const size_t at = static_cast<size_t>(o.order);
    if (!std::isnan(out.order_cv.rms[at])) out.notes.push_back("order " + std::to_string(o.order) + " chosen by " + std::to_string(plan.folds) +
                        "-fold cross-validation over orders 0.." + std::to_string(top) + " (CV RMS " +
                        fmt_g(out.order_cv.rms[at]) + " +- " + fmt_g(out.order_cv.rms_se[at], 2) +
                        " 1/sr; lowest order within 0.5% of the best mean square)");
    if (plan.choose_class) {
      const auto class_text = [](const OrderCrossValidation& cv, double rms) {
        return std::isnan(rms) ? std::string("no order determined")
                               : "CV RMS " + fmt_g(rms) + " 1/sr at order " + std::to_string(cv.chosen) + " of 0.." +
                                     std::to_string(cv.orders.back());
      };
      out.notes.push_back(modes_name(o.isotropic) + " chosen by cross-validation on the same folds: isotropic modes " +
                          class_text(out.isotropic_cv, out.cv_rms_isotropic) + ", general modes " +
                          class_text(out.general_cv, out.cv_rms_general));
    }
  } else {
    folds = assemble_folds(o.order, o.isotropic, wi, wr, values, w, plan.folds, o.progress, o.kernels,
                           single_gram_products(o.gram, positive, sample_fit_unknowns(o.order, o.isotropic)), o.split);
  }
  NormalEquations total = leading(folds.total, sample_fit_unknowns(o.order, o.isotropic));

  // 2. Lambda.
  if (plan.choose_tikhonov) {
    if (o.progress) o.progress("choosing lambda (GCV)", 0.0);
    const GcvChoice g = choose_tikhonov_gcv(total, o.order, o.isotropic, o.tikhonov_power);
    o.tikhonov = g.lambda;
    out.tikhonov_choice = "generalized cross-validation";
    out.notes.push_back("Tikhonov lambda " + fmt_g(g.lambda) + " (power " + fmt_g(o.tikhonov_power) +
                        ") chosen by generalized cross-validation");
  }

  // 3. The fit, and its fallbacks when the samples do not determine it. General modes that the normal
  // equations already show undetermined (unseen modes, no Cholesky factor, condition too large) are not
  // solved (their rank-revealing QR would be the slowest step and its result is not used).
  std::string why;
  // The CV error of this configuration (step 5) needs the folds' factorizations; they run beside the probe's, in
  // one pool of threads, and are used when no fallback changes the configuration (after a fallback they were
  // spent in vain: at most one CV's factorizations).
  // A Gram matrix with single-precision products that the fit cannot refine (sample_fit.hpp) is assembled again in
  // double, and probed again with its folds.
  std::optional<FoldScoring> early;
  NormalEquationsProbe probed;
  for (;;) {
    early.emplace(folds, o.order, o.tikhonov, o.tikhonov_power);
    std::vector<std::function<void()>> fold_jobs;
    for (int i = 0; i < early->folds(); ++i) fold_jobs.emplace_back([&early, i] { early->run(i); });
    probed = probe_normal_equations(total, o.rank_tolerance, o.kernels, fold_jobs);
    if (!total.single_products || single_gram_refinable(probed.determinacy)) break;
    folds = assemble_folds(o.order, o.isotropic, wi, wr, values, w, plan.folds, o.progress, o.kernels, false, o.split);
    total = leading(folds.total, sample_fit_unknowns(o.order, o.isotropic));
  }
  const NormalEquationsDeterminacy& pre = probed.determinacy;
  const bool pre_undetermined =
      o.tikhonov == 0.0 && (pre.unseen > 0 || !pre.factored || !(pre.condition <= kMaxDeterminedCondition));
  if (!o.isotropic && pre_undetermined) {
    why = "the samples do not determine the " + std::to_string(total.gram.rows()) + " " + modes_name(false) + " of order " +
          std::to_string(o.order) + " (" +
          (pre.unseen > 0 ? std::to_string(pre.unseen) + " unseen, " : std::string()) +
          (pre.factored ? "condition " + fmt_g(pre.condition) : std::string("A^T W A singular")) + ")";
  } else {
    out.fit = fit_samples(wi, wr, values, w, o, &total, &probed);
    if (!determined(out.fit))
      why = "the samples do not determine the " + std::to_string(out.fit.unknowns) + " " + modes_name(o.isotropic) +
            " of order " + std::to_string(o.order) + " (" + determinacy_text(out.fit) + ")";
  }
  if (!why.empty()) {
    bool done = false;
    if (!o.isotropic) {
      o.isotropic = true;
      folds = assemble_folds(o.order, true, wi, wr, values, w, plan.folds, o.progress, o.kernels, false, o.split);
      total = folds.total;
      out.fit = fit_samples(wi, wr, values, w, o, &total);
      if (determined(out.fit)) {
        out.fallback = why + "; fitted the isotropic modes instead (" + determinacy_text(out.fit) + ")";
        done = true;
      }
    }
    if (!done) {
      const GcvChoice g = choose_tikhonov_gcv(total, o.order, o.isotropic, o.tikhonov_power);
      o.tikhonov = g.lambda;
      out.tikhonov_choice = "generalized cross-validation";
      out.fit = fit_samples(wi, wr, values, w, o, &total);
      out.fallback = why + "; fitted the isotropic modes with Tikhonov lambda " + fmt_g(g.lambda) + " (power " +
                     fmt_g(o.tikhonov_power) + ", chosen by generalized cross-validation)";
    }
    out.notes.push_back("fallback: " + out.fallback);
  }

  if (out.fit.solver == std::string(kSingleGramSolver))
    out.notes.push_back("Gram matrix products in single precision (" + std::to_string(out.fit.samples) + " samples x " +
                        std::to_string(out.fit.unknowns) + "^2 unknowns), the solution refined to double accuracy in " +
                        std::to_string(out.fit.refinement_passes) + " passes over the samples");

  // 4. Scale check over the whole domain; regularization when the samples do not bound the fit.
  if (o.progress) o.progress("checking the fit's range", 0.0);
  out.max_abs_fit = max_abs_over_domain(out.fit);
  const double bound = kScaleGuardFactor * out.max_abs_sample;
  if (!(out.max_abs_fit <= bound)) {
    const double lambda_before = o.tikhonov;
    const GcvChoice g = choose_tikhonov_gcv(total, o.order, o.isotropic, o.tikhonov_power);
    // The grid's lambdas above the lambda used (and, when lambda was chosen by GCV, from the GCV-best one
    // upwards): the smallest bounded one by bisection (index `hi` bounded, `lo` not).
    const bool given_lambda = out.tikhonov_choice == "given";
    const double from = given_lambda ? o.tikhonov : std::max(g.lambda, o.tikhonov);
    std::vector<double> grid;
    for (double l : g.lambdas)
      if (l > from || (l == from && !given_lambda && l > 0.0)) grid.push_back(l);
    const auto fit_at = [&](double lambda) {
      SampleFitOptions r = o;
      r.tikhonov = lambda;
      SampleFitResult f = fit_samples(wi, wr, values, w, r, &total);
      const double m = max_abs_over_domain(f);
      return std::make_pair(std::move(f), m);
    };
    std::optional<std::pair<SampleFitResult, double>> found;
    if (!grid.empty()) {
      auto top = fit_at(grid.back());
      if (top.second <= bound) {
        long lo = -1, hi = static_cast<long>(grid.size()) - 1;
        found = std::move(top);
        while (hi - lo > 1) {
          const long mid = (lo + hi) / 2;
          auto at = fit_at(grid[static_cast<size_t>(mid)]);
          if (at.second <= bound) {
            hi = mid;
            found = std::move(at);
          } else {
            lo = mid;
          }
        }
      }
    }
    if (!found && plan.choose_order && o.order > 0) {
      // The order the cross-validation chose cannot be bounded, even regularized: choose again among the lower
      // orders (order 0, the weighted mean, is always bounded by the samples).
      SampleFitPlan lower = plan;
      lower.max_order = o.order - 1;
      CheckedSampleFit again = fit_samples_checked(wi, wr, values, weights, lower);
      again.notes.insert(again.notes.begin(), "order " + std::to_string(o.order) + " of the " + modes_name(o.isotropic) +
                                                  " reaches |f| = " + fmt_g(out.max_abs_fit) +
                                                  " 1/sr away from the samples even regularized: chosen again among orders 0.." +
                                                  std::to_string(o.order - 1));
      return again;
    }
    if (!found)
      throw UnsupportedError("sample fit: the samples cannot bound a fit of the " + modes_name(o.isotropic) + " of order " +
                             std::to_string(o.order) + ", even regularized: it reaches |f| = " + fmt_g(out.max_abs_fit) +
                             " 1/sr away from the samples, over " + fmt_g(kScaleGuardFactor, 2) +
                             " times the largest sample (" + fmt_g(out.max_abs_sample) +
                             " 1/sr); give a lower --order, or more samples");
    out.regularized_for_bound = true;
    out.unregularized_max_abs_fit = out.max_abs_fit;
    out.fit = std::move(found->first);
    out.max_abs_fit = found->second;
    o.tikhonov = out.fit.tikhonov;
    out.tikhonov_choice = given_lambda ? "smallest bounding lambda" : "generalized cross-validation, bounded";
    out.notes.push_back("regularized: lambda " + fmt_g(lambda_before) +
                        " would let the fit of order " + std::to_string(o.order) + " reach |f| = " +
                        fmt_g(out.unregularized_max_abs_fit) + " 1/sr away from the samples (over " + fmt_g(kScaleGuardFactor, 2) +
                        " times the largest, " + fmt_g(out.max_abs_sample) + " 1/sr); Tikhonov lambda " + fmt_g(o.tikhonov) +
                        " (power " + fmt_g(o.tikhonov_power) + "), " +
                        (given_lambda ? "the smallest of the GCV grid that bounds it (GCV's own choice " + fmt_g(g.lambda) + ")"
                                      : std::string("the GCV-best bounded one")) +
                        ": |f| <= " + fmt_g(out.max_abs_fit) +
                        " 1/sr, condition " + fmt_g(out.fit.condition) + ", effective degrees of freedom " +
                        fmt_g(out.fit.hat_trace) + " of " + std::to_string(out.fit.unknowns));
  }

  // 5. CV error of the final configuration (the folds of its modes): computed beside the probe unless a
  // fallback changed the modes or lambda.
  const bool same = why.empty() && !out.regularized_for_bound;
  if (same) early->refine_single();
  const OrderScore s = same ? early->score() : score_order(folds, o.order, o.tikhonov, o.tikhonov_power);
  out.cv_rms = s.determined ? std::sqrt(s.mse) : kNaN;
  return out;
}

}  // namespace icobrdf
