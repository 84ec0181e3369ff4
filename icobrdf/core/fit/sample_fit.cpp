#include "icobrdf/core/fit/sample_fit.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Householder>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/fit/lanczos.hpp"

namespace icobrdf {

namespace {

int unknown_count(int order, bool isotropic) {
  return isotropic ? isotropic_mode_count(order) : static_cast<int>(helmholtz_mode_count(order));
}

// Rows per chunk (of the QR path) and per panel (of the normal-equation assembly): keeps the design block
// near 4 million doubles (32 MB), so that a panel's rank-k update is one large matrix product.
Eigen::Index chunk_rows(int unknowns) { return std::max<Eigen::Index>(64, 4'000'000 / std::max(unknowns, 1)); }

// Rows per block of the design evaluated by one thread for a panel of the assembly: near 1 million doubles
// (8 MB, within the L3 cache of one socket), and at least 64 rows.
Eigen::Index block_rows(int unknowns) { return std::clamp<Eigen::Index>(1'000'000 / std::max(unknowns, 1), 64, 4096); }

// Rows per block of the passes over the samples (refinement, held-out errors): near 128 Ki doubles (1 MB), so
// that the block, read by two narrow products (A x, then A^T r), stays in a core's L2 cache between them. At
// 2,211 unknowns a pass over 20,000 samples with 5 solutions took 65-79 ms with 452-row blocks, 56-59 with
// 128, 41-46 with 32-64 (2-core AVX-512 Xeon, 2 MB L2 per core).
Eigen::Index pass_block_rows(int unknowns) { return std::clamp<Eigen::Index>(131'072 / std::max(unknowns, 1), 16, 4096); }


// The extreme eigenvalues of G by the Lanczos process (icobrdf/core/fit/lanczos.hpp): stopped when the Ritz
// pair's residual is below kConditionEigenTolerance of the Ritz value, so each eigenvalue, and the condition
// figure s_1 / sqrt(lambda_min), are within that relative error (the figure is read to two digits and
// compared with limits of 1e6 and more). kConditionMaxSteps bounds the applications of G (or of two triangular
// solves) when the spectrum's ends are tightly clustered; the Ritz value then still bounds its eigenvalue
// from the inside.
constexpr double kConditionEigenTolerance = 1e-4;
constexpr int kConditionMaxSteps = 300;
// Columns per block of inverse_diagonal: each block is one triangular solve with that many right-hand sides (a
// matrix-matrix solve, which needs tens of columns to run at Eigen's blocked speed), and 128 still leaves 9 blocks
// of the 1,035 unknowns of general order 8 (kMaxAutoOrderGeneral, sample_fit_selection.hpp) to share between threads.
constexpr Eigen::Index kInverseBlock = 128;
// The work (k^3 / 6 multiply-adds) below which inverse_diagonal runs on one thread: k < 670 unknowns, at most 1e8
// flops, a few milliseconds on one core; the same order as the rank update's kParallelRankUpdateMinWork
// (icobrdf/core/fit/dense_kernels.cpp), below which a parallel region costs more than it saves.
constexpr double kParallelInverseMinWork = 5e7;

void check_options(const SampleFitOptions& options, int channels) {
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
}

void check_rows(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values, const Eigen::VectorXd& weights,
                Eigen::Index channels) {
  const Eigen::Index s = wi.rows();
  if (wr.rows() != s || values.rows() != s || weights.size() != s || values.cols() != channels)
    throw ArgumentError("sample fit: expected wi, wr (rows x 3), values (rows x " + std::to_string(channels) +
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
}

// Rows (of `rows`, or all) with positive weight.
std::vector<Eigen::Index> positive_rows(const Eigen::VectorXd& weights, const std::vector<Eigen::Index>& rows) {
  std::vector<Eigen::Index> idx;
  if (rows.empty()) {
    for (Eigen::Index i = 0; i < weights.size(); ++i)
      if (weights[i] > 0.0) idx.push_back(i);
  } else {
    for (Eigen::Index i : rows)
      if (weights[i] > 0.0) idx.push_back(i);
  }
  return idx;
}

// This process's rows of the rows `idx` (SampleFitSplit; all of them when the fit is not split).
std::vector<Eigen::Index> part_of_rows(const std::vector<Eigen::Index>& idx, const SampleFitOptions& o) {
  if (!splits_work(o.split)) return idx;
  const auto [first, last] = o.split->rows_of_part(static_cast<long long>(idx.size()));
  return {idx.begin() + first, idx.begin() + last};
}

// Replaces `m` by its sum over the processes of a split fit (unchanged otherwise).
void sum_over_parts(const SampleFitOptions& o, std::vector<Eigen::MatrixXd>& m) {
  if (splits_work(o.split)) o.split->sum(m);
}

// Writes rows [lo, lo + m) of the rows `idx` into ab (W^(1/2) A: the modes at the samples times the square
// roots of the weights), yb (W^(1/2) Y) and w (the weights); ab, yb and w have m rows.
void design_rows(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                 const Eigen::VectorXd& weights, const std::vector<Eigen::Index>& idx, Eigen::Index lo, Eigen::Index m,
                 Eigen::Ref<Eigen::MatrixXd> ab, Eigen::Ref<Eigen::MatrixXd> yb, Eigen::Ref<Eigen::VectorXd> w) {
  RowMatrix3d a(m, 3), c(m, 3);
  for (Eigen::Index t = 0; t < m; ++t) {
    const Eigen::Index i = idx[static_cast<size_t>(lo + t)];
    a.row(t) = wi.row(i);
    c.row(t) = wr.row(i);
    w[t] = weights[i];
    yb.row(t) = values.row(i);
  }
  if (isotropic) ab = isotropic_modes_eval(order, a, c);
  else helmholtz_modes_eval(order, a, c, ab);
  const Eigen::ArrayXd sw = w.array().sqrt();
  ab.array().colwise() *= sw;
  yb.array().colwise() *= sw;
}

// Calls fn(thread, lo, W^(1/2) A_block, W^(1/2) Y_block, weights_block) for blocks of the rows idx[lo, lo + block), in parallel
// (one thread when `threads` is 1); progress (if any) from the calling thread. The design block is written
// into one buffer per thread, kept over the blocks: a fresh 8 MB block per call faults page by page again
// (320,000 of the 700,000 page faults of the 20,000-sample order-10 fit).
template <class Fn>
void for_each_block(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                    const Eigen::VectorXd& weights, const std::vector<Eigen::Index>& idx, int threads, const char* stage,
                    const FitProgress& progress, Fn fn) {
  const int k = unknown_count(order, isotropic);
  const auto n = static_cast<Eigen::Index>(idx.size());
  const Eigen::Index step = std::min(pass_block_rows(k), std::max<Eigen::Index>(n, 1));
  const Eigen::Index blocks = (n + step - 1) / step;
  std::vector<Eigen::MatrixXd> buffers(static_cast<size_t>(threads));
  std::atomic<Eigen::Index> done{0};
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    const Eigen::Index lo = b * step, m = std::min(n, lo + step) - lo;
    Eigen::VectorXd w(m);
    Eigen::MatrixXd yb(m, values.cols());
    Eigen::MatrixXd& buffer = buffers[static_cast<size_t>(omp_get_thread_num())];
    if (buffer.rows() != step || buffer.cols() != k) buffer.resize(step, k);
    auto ab = buffer.topRows(m);
    design_rows(order, isotropic, wi, wr, values, weights, idx, lo, m, ab, yb, w);
    fn(omp_get_thread_num(), lo, ab, yb, w);
    const Eigen::Index d = ++done;
    if (progress && omp_get_thread_num() == 0) progress(stage, static_cast<double>(d) / static_cast<double>(blocks));
  }
}

// Calls fn(W^(1/2) A_panel, W^(1/2) Y_panel, weights_panel) on the calling thread for consecutive panels of
// the rows `idx` (chunk_rows(unknowns) rows each), whose design rows `threads` threads evaluate in blocks
// first: fn then works on a panel with one large matrix product (itself parallel), and the sums run in the
// order of the rows whatever the threads.
template <class Fn>
void for_each_panel(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                    const Eigen::VectorXd& weights, const std::vector<Eigen::Index>& idx, int threads, const char* stage,
                    const FitProgress& progress, Fn fn) {
  const int k = unknown_count(order, isotropic);
  const auto n = static_cast<Eigen::Index>(idx.size());
  const Eigen::Index panel = std::min(chunk_rows(k), std::max<Eigen::Index>(n, 1));
  const Eigen::Index step = std::min(block_rows(k), panel);
  Eigen::MatrixXd ab(panel, k), yb(panel, values.cols());
  Eigen::VectorXd w(panel);
  for (Eigen::Index p0 = 0; p0 < n; p0 += panel) {
    const Eigen::Index m = std::min(n, p0 + panel) - p0, blocks = (m + step - 1) / step;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (Eigen::Index b = 0; b < blocks; ++b) {
      const Eigen::Index lo = b * step, mb = std::min(m, lo + step) - lo;
      design_rows(order, isotropic, wi, wr, values, weights, idx, p0 + lo, mb, ab.middleRows(lo, mb), yb.middleRows(lo, mb),
                  w.segment(lo, mb));
    }
    fn(ab.topRows(m), yb.topRows(m), w.head(m));
    if (progress) progress(stage, static_cast<double>(p0 + m) / static_cast<double>(n));
  }
}

// Below this many multiply-adds (rows x unknowns^2) one thread evaluates the design rows: a parallel region
// costs more than it saves (and much more on a loaded machine, where waiting threads spin).
constexpr double kParallelAssemblyMinWork = 5e7;

int assembly_threads(int unknowns, size_t rows) {
  if (static_cast<double>(rows) * unknowns * unknowns < kParallelAssemblyMinWork) return 1;
  return std::max(1, std::min<int>(omp_get_max_threads(), static_cast<int>(rows / 64) + 1));
}

// Below this many multiply-adds of the factorization (unknowns^3 / 3) the probe's pieces and the caller's jobs
// run one after the other: a parallel region costs more than it saves.
constexpr double kParallelProbeMinWork = 5e7;

// Largest eigenvalue of the symmetric positive semi-definite g (Lanczos on G).
double largest_eigenvalue(const Eigen::MatrixXd& g) {
  const SymmetricOperator apply = [&g](const Eigen::VectorXd& v, Eigen::VectorXd& out) {
    out.noalias() = g.selfadjointView<Eigen::Lower>() * v;
  };
  return lanczos_largest_eigenvalue(apply, Eigen::VectorXd::LinSpaced(g.rows(), 1.0, 2.0), kConditionEigenTolerance,
                                    kConditionMaxSteps).value;
}

// Smallest eigenvalue of g from its Cholesky factor (Lanczos on G^-1: two triangular solves a step).
double smallest_eigenvalue(const Eigen::LLT<Eigen::MatrixXd>& llt, Eigen::Index k) {
  const SymmetricOperator apply = [&llt](const Eigen::VectorXd& v, Eigen::VectorXd& out) { out = llt.solve(v); };
  const double rq = lanczos_largest_eigenvalue(apply, Eigen::VectorXd::LinSpaced(k, 2.0, 1.0), kConditionEigenTolerance,
                                               kConditionMaxSteps).value;
  return rq > 0.0 ? 1.0 / rq : 0.0;
}

// diag(G^-1) = the squared column norms of L^-1 (G = L L^T). Column j of L^-1 is zero above row j, so a
// block of columns [j0, j0 + w) solves only the trailing triangle L[j0:, j0:]: unknowns^3 / 6 multiply-adds
// instead of the unknowns^3 / 2 of a solve against the identity, in blocks spread over the threads (each
// column's arithmetic is fixed by the block size, not by the threads).
Eigen::VectorXd inverse_diagonal(const Eigen::LLT<Eigen::MatrixXd>& llt) {
  const Eigen::MatrixXd& l = llt.matrixLLT();
  const Eigen::Index k = l.rows();
  Eigen::VectorXd out(k);
  const Eigen::Index blocks = (k + kInverseBlock - 1) / kInverseBlock;
  const bool parallel = static_cast<double>(k) * k * k / 6.0 >= kParallelInverseMinWork;
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
  for (Eigen::Index b = 0; b < blocks; ++b) {
    const Eigen::Index j0 = b * kInverseBlock, w = std::min(kInverseBlock, k - j0), n = k - j0;
    Eigen::MatrixXd x = Eigen::MatrixXd::Identity(n, w);
    l.bottomRightCorner(n, n).triangularView<Eigen::Lower>().solveInPlace(x);
    out.segment(j0, w) = x.colwise().squaredNorm().transpose();
  }
  return out;
}

// Below this many entries the float panel is converted and added on one thread (a parallel region costs more).
constexpr double kParallelAddMinEntries = 1e6;

void fill_upper(Eigen::MatrixXd& g) { g.triangularView<Eigen::StrictlyUpper>() = g.transpose(); }

// g += ab^T ab on g's lower triangle with single-precision products: ab is scaled by 2^-e (its largest entry
// then in [1, 2), so neither its squares nor their sums leave float's range whatever the data's scale), rounded
// to float, its update accumulated in gf (zero on entry and again on return) and added to g times 2^(2e).
void single_rank_update(Eigen::MatrixXd& g, Eigen::MatrixXf& gf, Eigen::MatrixXf& af, const Eigen::Ref<const Eigen::MatrixXd>& ab) {
  const Eigen::Index k = g.cols();
  const bool parallel = static_cast<double>(ab.size()) >= kParallelAddMinEntries;
  double top = 0.0;
#pragma omp parallel for schedule(static) reduction(max : top) if (parallel)
  for (Eigen::Index j = 0; j < k; ++j) top = std::max(top, ab.col(j).cwiseAbs().maxCoeff());
  if (!(top > 0.0)) return;
  const int e = std::ilogb(top);
  const double scale = std::ldexp(1.0, -e);
  af.resize(ab.rows(), k);
#pragma omp parallel for schedule(static) if (parallel)
  for (Eigen::Index j = 0; j < k; ++j) af.col(j) = (ab.col(j) * scale).cast<float>();
  rank_update_lower(gf, af);
  const double back = std::ldexp(1.0, 2 * e);
#pragma omp parallel for schedule(dynamic, 64) if (static_cast<double>(k) * k >= kParallelAddMinEntries)
  for (Eigen::Index j = 0; j < k; ++j) {
    g.col(j).tail(k - j) += back * gf.col(j).tail(k - j).cast<double>();
    gf.col(j).tail(k - j).setZero();
  }
}

// sigma per channel and the standard errors from sqrt(diag(cov) / sigma^2) (unknowns), the RSS per channel and
// tr H.
void finish_uncertainty(SampleFitResult& out, const Eigen::VectorXd& unit_se, const Eigen::VectorXd& rss) {
  const double dof = static_cast<double>(out.samples) - out.hat_trace;
  out.noise_sigma.resize(rss.size());
  for (Eigen::Index c = 0; c < rss.size(); ++c)
    out.noise_sigma[c] = dof > 0.0 ? std::sqrt(std::max(rss[c], 0.0) / dof) : std::numeric_limits<double>::quiet_NaN();
  out.standard_error.resize(unit_se.size(), rss.size());
  for (Eigen::Index c = 0; c < rss.size(); ++c) out.standard_error.col(c) = unit_se * out.noise_sigma[c];
}

// Unseen modes (column norm <= tol s_1), the Cholesky factor and cond(W^(1/2) A) when it exists. `beside`: the
// caller's independent jobs, run in the same pool of threads (see probe_normal_equations).
NormalEquationsProbe probe(const NormalEquations& ne, double rank_tolerance, const DenseKernels* kernels,
                           const std::vector<std::function<void()>>& beside = {}) {
  NormalEquationsProbe p;
  const Eigen::MatrixXd& g = ne.gram;
  const Eigen::Index k = g.rows();
  const double eps = std::numeric_limits<double>::epsilon();
  p.tolerance = rank_tolerance >= 0.0 ? rank_tolerance : static_cast<double>(std::max<long long>(ne.samples, k)) * eps;
  const bool empty = ne.samples == 0 || k == 0;
  // Three independent pieces of work: the factorization followed by the smallest eigenvalue (Lanczos on G^-1),
  // the largest eigenvalue (Lanczos passes over G, bound by memory), and the caller's jobs. With threads to
  // spare and kernels that do not thread themselves they are tasks of one pool, each on one thread, so the
  // results do not depend on the threads.
  double lmax = 0.0, lmin = 0.0;
  std::shared_ptr<const Eigen::LLT<Eigen::MatrixXd>> llt;
  std::vector<std::function<void()>> work;
  if (!empty) {
    work.emplace_back([&] {
      llt = std::make_shared<const Eigen::LLT<Eigen::MatrixXd>>(cholesky(kernels, g));
      if (llt->info() == Eigen::Success) lmin = smallest_eigenvalue(*llt, k);
    });
    work.emplace_back([&] { lmax = largest_eigenvalue(g); });
  }
  work.insert(work.end(), beside.begin(), beside.end());
  std::vector<std::exception_ptr> failures(work.size());
  const auto run = [&](size_t j) {
    try {
      work[j]();
    } catch (...) {
      failures[j] = std::current_exception();
    }
  };
  const bool pooled = static_cast<double>(k) * k * k / 3.0 >= kParallelProbeMinWork && omp_get_max_threads() > 1 &&
                      !(kernels && kernels->threaded) && work.size() > 1;
  if (!pooled) {
    for (size_t j = 0; j < work.size(); ++j) run(j);
  } else {
#pragma omp parallel num_threads(std::min(omp_get_max_threads(), static_cast<int>(work.size())))
#pragma omp single
    for (size_t j = 0; j < work.size(); ++j) {
#pragma omp task firstprivate(j)
      run(j);
    }
  }
  for (const std::exception_ptr& f : failures)
    if (f) std::rethrow_exception(f);
  if (empty) return p;
  p.s1 = std::sqrt(std::max(lmax, 0.0));
  if (!(p.s1 > 0.0)) {
    p.determinacy.unseen = static_cast<int>(k);
    return p;
  }
  for (Eigen::Index j = 0; j < k; ++j)
    if (!(std::sqrt(std::max(g(j, j), 0.0)) > p.tolerance * p.s1)) ++p.determinacy.unseen;
  if (llt->info() != Eigen::Success) return p;
  p.llt = llt;
  if (!(lmin > 0.0)) return p;
  p.determinacy.factored = true;
  p.determinacy.condition = p.s1 / std::sqrt(lmin);
  return p;
}

// The normal-equation solve of the header comment, or nothing when the QR path must run. With a
// single-precision Gram, nothing and `needs_double` when that Gram cannot be refined (single_gram_refinable) or
// its refinement does not converge: the caller assembles G again in double.
std::optional<SampleFitResult> solve_normal_equations(const SampleFitOptions& options, const NormalEquations& ne,
                                                      const RowMatrix3d& wi, const RowMatrix3d& wr,
                                                      const Eigen::MatrixXd& values, const Eigen::VectorXd& weights,
                                                      const std::vector<Eigen::Index>& idx, const NormalEquationsProbe* probed,
                                                      bool& needs_double) {
  needs_double = false;
  const Eigen::MatrixXd& g = ne.gram;
  const Eigen::Index k = g.rows(), channels = ne.rhs.cols();
  const NormalEquationsProbe pr = probed ? *probed : probe(ne, options.rank_tolerance, options.kernels);
  if (ne.single_products && !single_gram_refinable(pr.determinacy)) {
    needs_double = true;
    return std::nullopt;
  }
  if (!pr.determinacy.factored || pr.determinacy.unseen > 0) return std::nullopt;
  const double cond = pr.determinacy.condition, tol = pr.tolerance, s1 = pr.s1;
  if (!(cond <= kNormalEquationsMaxCondition) || !(cond * tol < 1.0)) return std::nullopt;
  const Eigen::LLT<Eigen::MatrixXd>& llt = *pr.llt;

  SampleFitResult out;
  out.order = options.order;
  out.isotropic = options.isotropic;
  out.samples = ne.samples;
  out.unknowns = static_cast<int>(k);
  out.effective_rank = static_cast<int>(k);
  out.rank_tolerance = tol;
  out.rank_threshold = tol * s1;
  out.unseen.assign(static_cast<size_t>(k), false);
  out.condition = cond;
  out.tikhonov = options.tikhonov;
  out.weight_sum = ne.weight_sum;
  out.solver = ne.single_products ? kSingleGramSolver : "normal equations";

  Eigen::VectorXd d = Eigen::VectorXd::Zero(k);
  if (options.tikhonov > 0.0) d = options.tikhonov * tikhonov_penalties(options.order, options.isotropic, options.tikhonov_power);
  std::optional<Eigen::LLT<Eigen::MatrixXd>> penalized;
  if (options.tikhonov > 0.0) {
    Eigen::MatrixXd gl = g;
    gl.diagonal() += d;
    penalized.emplace(cholesky(options.kernels, std::move(gl)));
  }
  const Eigen::LLT<Eigen::MatrixXd>& lltl = penalized ? *penalized : llt;
  Eigen::MatrixXd x = lltl.solve(ne.rhs);

  // Refinement: c = A^T W (y - A x) and the weighted RSS from the samples, then x += (G + lambda D)^-1 (c - lambda D x).
  // One step with a double G; with a single-precision one, steps until the correction reaches the rounding floor.
  const int threads = assembly_threads(static_cast<int>(k), idx.size());
  const double floor = kRefinementFloor * cond;
  double previous = 0.0;  // the last correction's largest entry
  Eigen::VectorXd rss;
  for (;;) {
    std::vector<Eigen::MatrixXd> cs(static_cast<size_t>(threads), Eigen::MatrixXd::Zero(k, channels));
    std::vector<Eigen::VectorXd> rs(static_cast<size_t>(threads), Eigen::VectorXd::Zero(channels));
    for_each_block(options.order, options.isotropic, wi, wr, values, weights, idx, threads, "refining", options.progress,
                   [&](int t, Eigen::Index, const Eigen::Ref<const Eigen::MatrixXd>& ab, const Eigen::MatrixXd& yb, const Eigen::VectorXd&) {
                     const Eigen::MatrixXd r = yb - ab * x;
                     cs[static_cast<size_t>(t)].noalias() += ab.transpose() * r;
                     rs[static_cast<size_t>(t)] += r.colwise().squaredNorm().transpose();
                   });
    std::vector<Eigen::MatrixXd> sums{Eigen::MatrixXd::Zero(k, channels), Eigen::MatrixXd::Zero(channels, 1)};
    for (int t = 0; t < threads; ++t) {
      sums[0] += cs[static_cast<size_t>(t)];
      sums[1] += rs[static_cast<size_t>(t)];
    }
    sum_over_parts(options, sums);  // the other processes' rows
    const Eigen::MatrixXd c = std::move(sums[0]);
    rss = sums[1].col(0);
    const Eigen::MatrixXd dx = lltl.solve(c - d.asDiagonal() * x);
    for (Eigen::Index ch = 0; ch < channels; ++ch)
      rss[ch] = std::max(0.0, rss[ch] - 2.0 * dx.col(ch).dot(c.col(ch)) + dx.col(ch).dot(g.selfadjointView<Eigen::Lower>() * dx.col(ch)));
    x += dx;
    ++out.refinement_passes;
    if (!ne.single_products) break;
    if (!dx.allFinite()) break;
    const double last = dx.cwiseAbs().maxCoeff();
    if (refinement_converged(previous, last, x.cwiseAbs().maxCoeff(), floor)) break;
    previous = last;
    if (out.refinement_passes >= kMaxRefinementPasses) {
      needs_double = true;
      return std::nullopt;
    }
  }
  if (!x.allFinite()) {
    needs_double = ne.single_products;
    return std::nullopt;
  }
  out.modes = x;

  // Covariance / sigma^2: G^-1 (lambda = 0) or G_l^-1 G G_l^-1; tr H = k or tr(G_l^-1 G).
  Eigen::VectorXd unit_var(k);
  if (options.tikhonov == 0.0) {
    unit_var = inverse_diagonal(llt);
    out.hat_trace = static_cast<double>(k);
  } else {
    const Eigen::MatrixXd gli = lltl.solve(Eigen::MatrixXd::Identity(k, k));
    const Eigen::MatrixXd t = gli * g;
    unit_var = (t.array() * gli.array()).rowwise().sum().matrix();
    out.hat_trace = t.trace();
  }
  out.residual_rms.resize(channels);
  for (Eigen::Index ch = 0; ch < channels; ++ch) out.residual_rms[ch] = std::sqrt(rss[ch] / ne.weight_sum);
  finish_uncertainty(out, unit_var.cwiseMax(0.0).cwiseSqrt(), rss);
  for (Eigen::Index ch = 0; ch < channels; ++ch)
    out.channels.push_back(options.isotropic ? coefficients_from_ibsss(options.order, out.modes.col(ch))
                                             : coefficients_from_bsss(out.modes.col(ch)));
  return out;
}

}  // namespace

Eigen::MatrixXd sample_fit_modes(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr) {
  return isotropic ? isotropic_modes_eval(order, wi, wr) : helmholtz_modes_eval(order, wi, wr);
}

int sample_fit_unknowns(int order, bool isotropic) { return unknown_count(order, isotropic); }

double sample_fit_bytes(int unknowns, int folds) {
  const double k = unknowns;
  return 8.0 * k * k * (folds + kSampleFitSquares) + kSampleFitPanelBytes;
}

void require_sample_fit_memory(int order, bool isotropic, int folds) {
  const int k = unknown_count(order, isotropic);
  const double need = sample_fit_bytes(k, folds);
  const MemoryAvailable have = available_memory();
  if (need <= have.bytes) return;
  int fits = order;
  while (fits >= 0 && sample_fit_bytes(unknown_count(fits, isotropic), folds) > have.bytes) --fits;
  const char* modes = isotropic ? "isotropic" : "general";
  require_memory(need, have,
                 "a sample fit of the " + std::string(modes) + " modes of order " + std::to_string(order) + " (" + std::to_string(k) +
                     " unknowns" + (folds > 0 ? ", " + std::to_string(folds) + " folds" : "") + ")",
                 fits >= 0 ? "order " + std::to_string(fits) + " fits" + (isotropic ? "" : ", or --isotropic") : "");
}

HeldOutPass held_out_pass(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                          const Eigen::VectorXd& weights, const std::vector<int>& fold, const std::vector<Eigen::MatrixXd>& x) {
  const int k = unknown_count(order, isotropic);
  const auto folds = static_cast<Eigen::Index>(x.size());
  const Eigen::Index channels = values.cols();
  if (static_cast<Eigen::Index>(fold.size()) != values.rows() || weights.size() != values.rows())
    throw ArgumentError("held-out pass: " + std::to_string(fold.size()) + " fold numbers for " + std::to_string(values.rows()) + " samples");
  Eigen::MatrixXd xs(k, folds * channels);  // the solutions side by side
  for (Eigen::Index f = 0; f < folds; ++f) {
    if (x[static_cast<size_t>(f)].rows() != k || x[static_cast<size_t>(f)].cols() != channels)
      throw ArgumentError("held-out pass: solution " + std::to_string(f) + " is not " + std::to_string(k) + " x " + std::to_string(channels));
    xs.middleCols(f * channels, channels) = x[static_cast<size_t>(f)];
  }
  std::vector<Eigen::Index> idx;
  for (Eigen::Index i = 0; i < weights.size(); ++i)
    if (weights[i] > 0.0 && fold[static_cast<size_t>(i)] >= 0) {
      if (fold[static_cast<size_t>(i)] >= folds)
        throw ArgumentError("held-out pass: sample " + std::to_string(i) + " is in fold " + std::to_string(fold[static_cast<size_t>(i)]) +
                            ", expected < " + std::to_string(folds));
      idx.push_back(i);
    }
  const int threads = assembly_threads(k, idx.size());
  std::vector<Eigen::MatrixXd> cs(static_cast<size_t>(threads), Eigen::MatrixXd::Zero(k, folds * channels));
  std::vector<Eigen::MatrixXd> hs(static_cast<size_t>(threads), Eigen::MatrixXd::Zero(channels, folds));
  for_each_block(order, isotropic, wi, wr, values, weights, idx, threads, "cross-validating", {},
                 [&](int t, Eigen::Index lo, const Eigen::Ref<const Eigen::MatrixXd>& ab, const Eigen::MatrixXd& yb, const Eigen::VectorXd&) {
                   Eigen::MatrixXd r = -(ab * xs);
                   for (Eigen::Index f = 0; f < folds; ++f) r.middleCols(f * channels, channels) += yb;
                   for (Eigen::Index j = 0; j < r.rows(); ++j) {  // a row of fold g: held out by g, trains the others
                     const Eigen::Index g = fold[static_cast<size_t>(idx[static_cast<size_t>(lo + j)])];
                     auto own = r.row(j).segment(g * channels, channels);
                     hs[static_cast<size_t>(t)].col(g) += own.cwiseAbs2().transpose();
                     own.setZero();
                   }
                   cs[static_cast<size_t>(t)].noalias() += ab.transpose() * r;
                 });
  HeldOutPass out;
  Eigen::MatrixXd c = Eigen::MatrixXd::Zero(k, folds * channels), h = Eigen::MatrixXd::Zero(channels, folds);
  for (int t = 0; t < threads; ++t) {
    c += cs[static_cast<size_t>(t)];
    h += hs[static_cast<size_t>(t)];
  }
  for (Eigen::Index f = 0; f < folds; ++f) {
    out.c.push_back(c.middleCols(f * channels, channels));
    out.held.push_back(h.col(f));
  }
  return out;
}

bool single_gram_products(GramPrecision gram, long long samples, int unknowns) {
  if (gram != GramPrecision::Automatic) return gram == GramPrecision::Single;
  return static_cast<double>(samples) * unknowns * unknowns >= kSingleGramMinWork;
}

bool single_gram_refinable(const NormalEquationsDeterminacy& d) {
  return d.unseen == 0 && d.factored && d.condition <= kSingleGramMaxCondition;
}

NormalEquationsDeterminacy normal_equations_determinacy(const NormalEquations& ne, double rank_tolerance) {
  return probe(ne, rank_tolerance, nullptr).determinacy;
}

NormalEquationsProbe probe_normal_equations(const NormalEquations& ne, double rank_tolerance, const DenseKernels* kernels,
                                            const std::vector<std::function<void()>>& beside) {
  return probe(ne, rank_tolerance, kernels, beside);
}

void check_sample_fit_input(const SampleFitOptions& options, const RowMatrix3d& wi, const RowMatrix3d& wr,
                            const Eigen::MatrixXd& values, const Eigen::VectorXd& weights) {
  check_options(options, static_cast<int>(values.cols()));
  check_rows(wi, wr, values, weights, values.cols());
}

namespace {

// assemble_normal_equations over the rows `idx` (all of positive weight).
NormalEquations assemble_rows(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                              const Eigen::VectorXd& weights, const std::vector<Eigen::Index>& idx, const FitProgress& progress,
                              const DenseKernels* kernels, bool single_products) {
  const int k = unknown_count(order, isotropic);
  const Eigen::Index channels = values.cols();
  NormalEquations ne;
  ne.gram = Eigen::MatrixXd::Zero(k, k);
  ne.rhs = Eigen::MatrixXd::Zero(k, channels);
  ne.yy = Eigen::VectorXd::Zero(channels);
  ne.single_products = single_products;
  Eigen::MatrixXf gf, af;  // single products: the panel's float Gram (lower triangle, zero between panels) and design
  if (single_products) gf = Eigen::MatrixXf::Zero(k, k);
  for_each_panel(order, isotropic, wi, wr, values, weights, idx, assembly_threads(k, idx.size()), "assembling", progress,
                 [&](const Eigen::Ref<const Eigen::MatrixXd>& ab, const Eigen::Ref<const Eigen::MatrixXd>& yb,
                     const Eigen::Ref<const Eigen::VectorXd>& w) {
                   if (single_products) single_rank_update(ne.gram, gf, af, ab);
                   else rank_update_lower(kernels, ne.gram, ab);
                   ne.rhs.noalias() += ab.transpose() * yb;
                   ne.yy += yb.colwise().squaredNorm().transpose();
                   ne.weight_sum += w.sum();
                 });
  fill_upper(ne.gram);
  ne.samples = static_cast<long long>(idx.size());
  return ne;
}

}  // namespace

void sum_normal_equations(const std::shared_ptr<const SampleFitSplit>& split, std::vector<NormalEquations>& ne) {
  if (!splits_work(split)) return;
  std::vector<Eigen::MatrixXd> m;
  for (NormalEquations& e : ne) {
    m.push_back(std::move(e.gram));
    m.push_back(std::move(e.rhs));
    m.push_back(e.yy);
    m.push_back(Eigen::Vector2d(e.weight_sum, static_cast<double>(e.samples)));
  }
  split->sum(m);
  for (size_t k = 0; k < ne.size(); ++k) {
    NormalEquations& e = ne[k];
    e.gram = std::move(m[4 * k]);
    e.rhs = std::move(m[4 * k + 1]);
    e.yy = m[4 * k + 2].col(0);
    e.weight_sum = m[4 * k + 3](0, 0);
    e.samples = std::llround(m[4 * k + 3](1, 0));  // a count below 2^53: exact in double
  }
}

NormalEquations assemble_normal_equations(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr,
                                          const Eigen::MatrixXd& values, const Eigen::VectorXd& weights,
                                          const std::vector<Eigen::Index>& rows, const FitProgress& progress,
                                          const DenseKernels* kernels, bool single_products) {
  return assemble_rows(order, isotropic, wi, wr, values, weights, positive_rows(weights, rows), progress, kernels, single_products);
}

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
  check_options(options, channels);
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

void SampleFitAccumulator::merge_parts() {
  if (!splits_work(options_.split)) return;
  const auto parts = static_cast<size_t>(options_.split->parts), part = static_cast<size_t>(options_.split->part);
  std::vector<Eigen::MatrixXd> m(parts + 1, Eigen::MatrixXd::Zero(r_.rows(), r_.cols()));
  m[part] = r_;
  m[parts] = Eigen::Vector2d(weight_sum_, static_cast<double>(samples_));
  options_.split->sum(m);  // every process's factor, each in its own slot (the others add zeros)
  r_.setZero();
  for (size_t p = 0; p < parts; ++p) absorb(m[p]);
  weight_sum_ = m[parts](0, 0);
  samples_ = std::llround(m[parts](1, 0));
}

void SampleFitAccumulator::add(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                               const Eigen::VectorXd& weights) {
  const Eigen::Index s = wi.rows();
  check_rows(wi, wr, values, weights, channels_);
  const Eigen::Index step = chunk_rows(unknowns_);
  for (Eigen::Index b = 0; b < s; b += step) {
    if (options_.progress) options_.progress("QR of the samples", static_cast<double>(b) / static_cast<double>(s));
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
    block.leftCols(unknowns_) = sw.asDiagonal() * sample_fit_modes(options_.order, options_.isotropic, a, c);
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
  Eigen::MatrixXd m_op = Eigen::MatrixXd::Zero(ks, k);  // x = M z (header comment)
  if (ks > 0) {
    Eigen::BDCSVD<Eigen::MatrixXd> svd(rs, Eigen::ComputeThinU | Eigen::ComputeThinV);
    out.singular_values = svd.singularValues();
    out.effective_rank = 0;
    for (Eigen::Index t = 0; t < out.singular_values.size(); ++t)
      if (out.singular_values[t] > out.rank_threshold) ++out.effective_rank;
    if (out.effective_rank > 0)
      out.condition = out.singular_values[0] / out.singular_values[out.effective_rank - 1];
    if (options_.tikhonov == 0.0) {
      const int r = out.effective_rank;
      m_op = svd.matrixV().leftCols(r) * (out.singular_values.head(r).cwiseInverse().asDiagonal() *
                                          svd.matrixU().leftCols(r).transpose());
    } else {
      const Eigen::VectorXd d = tikhonov_penalties(options_.order, options_.isotropic, options_.tikhonov_power);
      Eigen::MatrixXd aug = Eigen::MatrixXd::Zero(k + ks, ks);
      aug.topRows(k) = rs;
      for (Eigen::Index t = 0; t < ks; ++t) aug(k + t, t) = std::sqrt(options_.tikhonov * d[seen[static_cast<size_t>(t)]]);
      Eigen::BDCSVD<Eigen::MatrixXd> reg(aug, Eigen::ComputeThinU | Eigen::ComputeThinV);
      const Eigen::VectorXd sv = reg.singularValues();
      const double thr = out.rank_tolerance * (sv.size() ? sv[0] : 0.0);
      int r = 0;
      while (r < sv.size() && sv[r] > thr) ++r;
      // The right-hand side of the stacked system is [z; 0]: only the top k rows of U act.
      m_op = reg.matrixV().leftCols(r) * (sv.head(r).cwiseInverse().asDiagonal() *
                                          reg.matrixU().topRows(k).leftCols(r).transpose());
    }
    xs = m_op * z;
  }
  out.null_space_dimension = k - out.effective_rank;
  out.modes = Eigen::MatrixXd::Zero(k, channels_);
  for (Eigen::Index t = 0; t < ks; ++t) out.modes.row(seen[static_cast<size_t>(t)]) = xs.row(t);
  out.tikhonov = options_.tikhonov;
  out.weight_sum = weight_sum_;
  out.solver = "QR";
  // tr H = tr(R_s M); the hat matrix of the rows is Q [R_s M] Q^T.
  out.hat_trace = ks > 0 ? (rs.array() * m_op.transpose().array()).sum() : 0.0;

  // Weighted residual: ||W^(1/2)(A x - y)||^2 = ||R11 x - z||^2 + ||R22 e_c||^2.
  out.residual_rms.resize(channels_);
  Eigen::VectorXd rss(channels_);
  for (int c = 0; c < channels_; ++c) {
    const double fit_part = (r11 * out.modes.col(c) - z.col(c)).squaredNorm();
    const double rest = r22.col(c).squaredNorm();
    rss[c] = fit_part + rest;
    out.residual_rms[c] = std::sqrt(rss[c] / weight_sum_);
  }
  Eigen::VectorXd unit_se = Eigen::VectorXd::Constant(k, std::numeric_limits<double>::quiet_NaN());
  for (Eigen::Index t = 0; t < ks; ++t) unit_se[seen[static_cast<size_t>(t)]] = m_op.row(t).norm();
  finish_uncertainty(out, unit_se, rss);
  for (int c = 0; c < channels_; ++c)
    out.channels.push_back(options_.isotropic ? coefficients_from_ibsss(options_.order, out.modes.col(c))
                                              : coefficients_from_bsss(out.modes.col(c)));
  return out;
}

SampleFitResult fit_samples(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                            const Eigen::VectorXd& weights, const SampleFitOptions& options,
                            const NormalEquations* assembled, const NormalEquationsProbe* probed) {
  const Eigen::VectorXd w = weights.size() == 0 ? Eigen::VectorXd::Ones(wi.rows()).eval() : weights;
  check_sample_fit_input(options, wi, wr, values, w);
  const std::vector<Eigen::Index> all = positive_rows(w, {});
  if (all.empty()) throw ArgumentError("sample fit: no sample with positive weight");
  const std::vector<Eigen::Index> idx = part_of_rows(all, options);  // this process's rows (SampleFitSplit)
  const int k = unknown_count(options.order, options.isotropic);
  if (!assembled) require_sample_fit_memory(options.order, options.isotropic, 0);
  const auto assemble = [&](bool single) {
    std::vector<NormalEquations> ne{assemble_rows(options.order, options.isotropic, wi, wr, values, w, idx, options.progress, options.kernels, single)};
    sum_normal_equations(options.split, ne);
    return std::move(ne[0]);
  };
  NormalEquations own;
  if (!assembled) own = assemble(single_gram_products(options.gram, static_cast<long long>(all.size()), k));
  if (!assembled) probed = nullptr;  // a probe of other normal equations
  const NormalEquations* ne = assembled ? assembled : &own;
  if (ne->gram.rows() != k || ne->samples != static_cast<long long>(all.size()))
    throw ArgumentError("sample fit: the assembled normal equations do not match the samples and modes");
  bool needs_double = false;
  if (auto fast = solve_normal_equations(options, *ne, wi, wr, values, w, idx, probed, needs_double)) return *fast;
  if (needs_double) {  // a single-precision Gram that cannot be refined: assemble it again in double
    own = assemble(false);
    if (auto fast = solve_normal_equations(options, own, wi, wr, values, w, idx, nullptr, needs_double)) return *fast;
  }
  SampleFitAccumulator acc(options, static_cast<int>(values.cols()));
  if (!splits_work(options.split)) {
    acc.add(wi, wr, values, w);
  } else {  // this process's rows (the others' weights 0: skipped), then every process's factor
    Eigen::VectorXd mine = Eigen::VectorXd::Zero(w.size());
    for (const Eigen::Index i : idx) mine[i] = w[i];
    acc.add(wi, wr, values, mine);
    acc.merge_parts();
  }
  return acc.solve();
}

}  // namespace icobrdf
