#pragma once
// Weighted least-squares fit of scattered BRDF samples onto the Helmholtz modes (or the isotropic modes).
//
// Data: S samples (w_i, w_r, f) with weights w_s >= 0; wi, wr are S x 3 unit vectors (z >= 0, normal +z,
// both pointing away from the surface), values S x channels [1/sr]. Unknowns: the coefficients x of the
// modes up to total order N in the library order (icobrdf/core/basis/helmholtz_modes.hpp: M(M+1)/2 BSSS modes;
// icobrdf/core/basis/isotropic_modes.hpp with `isotropic`: Table 2 order). With A (S x unknowns) the modes at the samples
// and W = diag(w_s), per channel
//     minimize  || W^(1/2) (A x - y) ||^2 + lambda sum_k d_k x_k^2,
//     d_k = (n(n+2) + m(m+2))^p  for the mode built from K_n^. (x) K_m^. (isotropic: I_nm^l),
// an order-graded Tikhonov penalty: n(n+2) is the eigenvalue of the Zernike polynomials of radial order n
// under their Sturm-Liouville (disk Laplacian-like) operator, so p = 1 penalizes roughness; the order-0
// mode has d = 0 and is never shrunk (p = 0 gives plain ridge regression, d = 1 for every mode).
//
// Solver (rank revealing, minimum norm). The rows are reduced by a streaming Householder QR of
// [W^(1/2) A | W^(1/2) Y] (chunks of rows, so millions of samples need only unknowns^2 memory); then
//   * unseen modes: columns of W^(1/2) A whose norm is <= tau are modes the data cannot see; their
//     coefficients are set to exactly 0 and they take no part in the solve;
//   * the singular values s_1 >= s_2 >= ... of W^(1/2) A (those of the triangular factor) give the effective
//     rank r = #{ s_k > tau },  tau = tol * s_1,  tol = max(S, unknowns) * machine epsilon unless given
//     (the LAPACK / MATLAB numerical-rank convention);
//   * lambda = 0: x = V_r S_r^-1 U_r^T z (truncated SVD): the minimum-norm least-squares solution, with no
//     component in the numerical null space (the least-committed solution of K&vD's velvet example);
//     lambda > 0: the penalized system [R; sqrt(lambda D)] x = [z; 0] solved by SVD with the same truncation.
// Reported: effective rank, null-space dimension (unknowns - rank), unseen modes, singular values, and the
// weighted residual RMS per channel, sqrt(sum_s w_s (A x - y)_s^2 / sum_s w_s).
// Accuracy: data in the span of the modes are recovered to ~ cond(W^(1/2) A) * 1e-16 relative.
//
// Fast path (fit_samples). The normal equations G = A^T W A, A^T W Y are assembled in panels of rows
// (the modes of a panel evaluated by all threads, then one rank-k update of G by SampleFitOptions::kernels:
// Eigen's by default, OpenBLAS's dsyrk from icobrdf/io), which costs S k^2 flops instead of the QR's
// 2 S k^2 and needs no restacking. When every mode is seen and the Cholesky factor of
// G exists with cond(W^(1/2) A) = sqrt(lambda_max(G) / lambda_min(G)) <= kNormalEquationsMaxCondition
// (extreme eigenvalues by Lanczos on G and G^-1, icobrdf/core/fit/lanczos.hpp) and <= 1 / rank tolerance, the fit solves
// (G + lambda D) x = A^T W y by Cholesky and applies one step of iterative refinement with the residual
// recomputed from the samples (corrected semi-normal equations: the rounding error of forming G, of order
// cond(G) eps <= 1e-4, is reduced by that factor again). Otherwise (unseen modes, rank deficiency, ill
// conditioning) it streams the rows through the rank-revealing QR above. `solver` says which ran.
//
// Single-precision Gram products (GramPrecision::Single; Automatic picks them for fits of at least
// kSingleGramMinWork multiply-adds). The rank-k update of each panel runs in float, about twice as fast as in
// double (16 lanes instead of 8 on AVX-512), on the panel scaled by a power of two (no overflow or underflow
// for any data scale) and is added to the double G; G then carries a rounding error of relative size about
// sqrt(panel rows) * 2^-24 (~1e-6) instead of ~1e-15. The fit removes it: the iterative refinement above runs
// until the correction is below kRefinementFloor * cond(W^(1/2) A) of the solution (each step divides the error by
// about 1 / (cond(G) * 1e-6)), so the coefficients reach the double path's accuracy. Used only while the
// probe of G finds every mode seen, a factor and cond(W^(1/2) A) <= kSingleGramMaxCondition (each step then
// gains at least 2 digits); otherwise, and when the refinement does not converge in kMaxRefinementPasses,
// the fit assembles G again in double. What keeps the single-precision rounding: the condition figure and
// the standard errors (relative error ~ cond(G) * 1e-6, far below the digits they are read to). The
// cross-validation folds of icobrdf/core/fit/sample_fit_selection.hpp are refined the same way (held_out_pass).
//
// Uncertainty (both paths). With z = Q^T W^(1/2) y the estimate is x = M z (M = G_lambda^-1 R^T, or
// V_r S_r^-1 U_r^T for the truncated SVD), so for independent errors of variance sigma^2 / w_s (weights are
// inverse relative variances; duplicate counts are), cov(x) = sigma^2 M M^T:
//   lambda = 0, full rank:  sigma^2 (A^T W A)^-1;   lambda > 0:  sigma^2 G_l^-1 A^T W A G_l^-1.
// sigma^2 is estimated per channel as RSS_w / (S - tr H), H the hat matrix (tr H = the rank for lambda = 0,
// sum of the filter factors otherwise). standard_error(k, c) = sigma_c sqrt(cov_kk / sigma^2); NaN for
// unseen modes (their 0 is a choice, not an estimate) and when S <= tr H. With a null space the figures
// describe the spread of the minimum-norm estimate only: the undetermined combinations have no error bar.
#include <Eigen/Core>

#include <Eigen/Cholesky>

#include <functional>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "icobrdf/core/fit/dense_kernels.hpp"
#include "icobrdf/core/fit/fit_progress.hpp"
#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf {

// The normal equations are used only when cond(W^(1/2) A) is at most this: cond(G) = 1e12 leaves
// cond(G) eps ~ 2e-4 < 1, so one refinement step restores QR-level accuracy (Bjorck, "Numerical Methods
// for Least Squares Problems", sec. 2.9, corrected semi-normal equations).
inline constexpr double kNormalEquationsMaxCondition = 1e6;

// Below this condition of W^(1/2) A a Gram matrix with single-precision products is refined to double accuracy
// in a few steps: cond(G) = 1e4 times its ~1e-6 relative rounding leaves a contraction of 1e-2 per step.
inline constexpr double kSingleGramMaxCondition = 100.0;
// Work (samples x unknowns^2 multiply-adds of the Gram matrix) from which GramPrecision::Automatic takes
// single-precision products: 1e10 is ~0.15 s of double products on the 2-core machine of benchmarks/RESULTS.md,
// where halving them outweighs the extra refinement passes (each ~2 samples x unknowns multiply-adds).
inline constexpr double kSingleGramMinWork = 1e10;
// Refinement passes over the samples with a single-precision Gram before the fit falls back to a double one.
inline constexpr int kMaxRefinementPasses = 12;
// The refinement stops when the error left, estimated as the last correction d_j times rho / (1 - rho) with
// rho = |d_j| / |d_j-1| its measured contraction (or the correction itself once it is this small), is at most this
// times cond(W^(1/2) A) times the solution (largest entries): the attainable accuracy of the corrected
// semi-normal equations is ~ cond eps (Bjorck, sec. 2.9).
inline constexpr double kRefinementFloor = 16.0 * std::numeric_limits<double>::epsilon();

// Whether a refinement whose corrections had largest entries `previous` (0 before the second) and `last`, on a
// solution of largest entry `size`, has converged to `floor` (relative), by the rule above.
inline bool refinement_converged(double previous, double last, double size, double floor) {
  if (last <= floor * size) return true;
  if (!(previous > 0.0) || !(last < previous)) return false;
  const double rho = last / previous;
  return last * rho / (1.0 - rho) <= floor * size;
}

// Precision of the products of the Gram matrix's rank-k updates (see "Single-precision Gram products").
enum class GramPrecision { Automatic, Double, Single };

// A fit split over processes (`mpirun icobrdf fit`, icobrdf/cluster/distributed_projection.hpp). Every process
// holds every sample; process `part` of `parts` passes over its contiguous share of the rows of positive weight
// (rows [n part / parts, n (part + 1) / parts) of them) and nothing else, and every pass ends in `sum`, which
// replaces matrices (the same sizes on every process) by their sum over the processes, added in part order,
// every process getting the sum. The normal equations, each refinement pass and the residual are sums; the QR
// path's triangular factors are combined instead (each process's factor is gathered through `sum` and the
// factors absorbed in part order: parts x (unknowns + channels)^2 doubles per process). Every decision (the
// solver, the refinement's end) is then taken from the same summed figures on every process, so all reach
// the same solution: the same bits for a fixed number of processes running the same build on the same
// instruction set, and one process's solution up to the order of the sums. `sum` is collective: every
// process calls it the same number of times.
struct SampleFitSplit {
  int part = 0, parts = 1;
  std::function<void(std::vector<Eigen::MatrixXd>&)> sum;
  // This process's positions [first, second) among n rows of positive weight.
  std::pair<long long, long long> rows_of_part(long long n) const { return {n * part / parts, n * (part + 1) / parts}; }
};
// Whether `split` divides the work (not null, more than one part).
inline bool splits_work(const std::shared_ptr<const SampleFitSplit>& split) { return split && split->parts > 1; }

// SampleFitResult::solver of a normal-equation fit whose Gram matrix had single-precision products.
inline constexpr const char* kSingleGramSolver = "normal equations, single-precision Gram";

struct SampleFitOptions {
  int order = 4;             // total order N of the modes
  bool isotropic = false;    // fit the isotropic modes I_nm^l instead of the general Helmholtz modes
  double tikhonov = 0.0;     // lambda >= 0
  double tikhonov_power = 1.0;  // p >= 0
  double rank_tolerance = -1.0;  // relative tol on singular values; < 0: max(S, unknowns) * eps
  FitProgress progress;          // optional
  // The rank-k update and Cholesky kernels of the normal-equation path (icobrdf/core/fit/dense_kernels.hpp);
  // null: Eigen's. Not owned; must outlive the fit.
  const DenseKernels* kernels = nullptr;
  // Products of the Gram matrix when the fit assembles it (fit_samples without `assembled`; fit_samples_checked).
  GramPrecision gram = GramPrecision::Automatic;
  // Optional: this process's part of a fit split over processes (SampleFitSplit): fit_samples and
  // fit_samples_checked (icobrdf/core/fit/sample_fit_selection.hpp) pass over its rows only.
  std::shared_ptr<const SampleFitSplit> split;
};

struct SampleFitResult {
  int order = 0;
  bool isotropic = false;
  Eigen::MatrixXd modes;                  // unknowns x channels: the mode coefficients (BSSS or IBSSS order)
  std::vector<Eigen::MatrixXd> channels;  // per channel the symmetric M x M coefficient matrix C
  long long samples = 0;                  // rows used (weight > 0)
  int unknowns = 0;
  int effective_rank = 0;                 // numerical rank of W^(1/2) A
  int null_space_dimension = 0;           // unknowns - effective_rank
  int unseen_modes = 0;                   // modes with a zero column (coefficient exactly 0)
  double rank_tolerance = 0.0;            // relative tolerance used
  double rank_threshold = 0.0;            // tau = rank_tolerance * s_1
  Eigen::VectorXd singular_values;        // of W^(1/2) A restricted to the seen modes, descending
  Eigen::VectorXd residual_rms;           // per channel, weighted [1/sr]
  std::vector<bool> unseen;               // per unknown: true when its column is (numerically) zero
  double condition = std::numeric_limits<double>::quiet_NaN();  // s_1 / s_rank of W^(1/2) A on the kept part
  double tikhonov = 0.0;                  // lambda used
  double hat_trace = 0.0;                 // tr H: effective number of parameters
  double weight_sum = 0.0;                // sum of the weights of the rows used
  Eigen::VectorXd noise_sigma;            // per channel: sigma (error of a weight-1 sample) [1/sr]; NaN if S <= tr H
  Eigen::MatrixXd standard_error;         // unknowns x channels (see the header comment); NaN where undefined
  const char* solver = "";                // "normal equations", "normal equations, single-precision Gram" or "QR"
  int refinement_passes = 0;              // passes over the samples that refined the normal-equation solution
};

// Weighted normal equations of the modes at samples: gram = A^T W A (unknowns x unknowns, both triangles),
// rhs = A^T W Y (unknowns x channels), yy = diag(Y^T W Y) per channel, over the rows listed in `rows`
// (all rows when empty) whose weight is > 0. Assembled in panels of rows (the modes of a panel evaluated by
// all threads, then one rank-k update by `kernels`, Eigen's when null), so the sums run in the order of the
// rows whatever the thread count.
struct NormalEquations {
  Eigen::MatrixXd gram;
  bool single_products = false;  // gram's rank-k products ran in single precision (rhs and yy are double always)
  Eigen::MatrixXd rhs;
  Eigen::VectorXd yy;
  double weight_sum = 0.0;
  long long samples = 0;
};
// The normal equations of each process's rows -> the sums over every process's, in one collective sum of all of
// `ne` (nothing when `split` does not divide the work).
void sum_normal_equations(const std::shared_ptr<const SampleFitSplit>& split, std::vector<NormalEquations>& ne);
NormalEquations assemble_normal_equations(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr,
                                          const Eigen::MatrixXd& values, const Eigen::VectorXd& weights,
                                          const std::vector<Eigen::Index>& rows = {}, const FitProgress& progress = {},
                                          const DenseKernels* kernels = nullptr, bool single_products = false);

// One pass over the samples for K training problems at once (the cross-validation folds of
// icobrdf/core/fit/sample_fit_selection.hpp): fold[i] is the fold of row i of `values` in [0, K) (-1: not used; rows of
// weight 0 are skipped too), x[f] (unknowns x channels) the solution trained without fold f. Returns per fold
// c[f] = A_-f^T W (y - A_-f x_f), the residual that refines training problem f, and held[f] = the sum over
// the rows of fold f of w (y - A x_f)^2 per channel, its held-out error, both from the samples in double.
struct HeldOutPass {
  std::vector<Eigen::MatrixXd> c;
  std::vector<Eigen::VectorXd> held;
};
HeldOutPass held_out_pass(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                          const Eigen::VectorXd& weights, const std::vector<int>& fold, const std::vector<Eigen::MatrixXd>& x);

// Whether a fit of `samples` samples and `unknowns` unknowns assembles its Gram matrix with single-precision
// products (Automatic: when samples x unknowns^2 >= kSingleGramMinWork).
bool single_gram_products(GramPrecision gram, long long samples, int unknowns);

// What the normal equations say about determinacy before any solve: modes with column norm <= tol s_1
// (tol: the rank tolerance, negative for the default), whether G has a Cholesky factor, and then
// cond(W^(1/2) A) = sqrt(lambda_max(G) / lambda_min(G)) (Lanczos on G and on G^-1 through the factor, each
// eigenvalue to 1e-4 relative, icobrdf/core/fit/lanczos.hpp; NaN without a factor).
struct NormalEquationsDeterminacy {
  int unseen = 0;
  bool factored = false;
  double condition = std::numeric_limits<double>::quiet_NaN();
};
NormalEquationsDeterminacy normal_equations_determinacy(const NormalEquations& ne, double rank_tolerance = -1.0);

// Whether a single-precision Gram matrix with this probe can be refined to double accuracy (every mode seen, a
// factor, cond(W^(1/2) A) <= kSingleGramMaxCondition).
bool single_gram_refinable(const NormalEquationsDeterminacy& d);

// The same figures with what the solve reuses: the tolerance, s_1 = sqrt(lambda_max(G)) and the Cholesky
// factor of G (null when G has none, or when a mode is unseen). `kernels` factor G (Eigen's when null).
struct NormalEquationsProbe {
  NormalEquationsDeterminacy determinacy;
  double tolerance = 0.0;  // relative rank tolerance used
  double s1 = 0.0;         // largest singular value of W^(1/2) A
  std::shared_ptr<const Eigen::LLT<Eigen::MatrixXd>> llt;
};
// `beside`: independent jobs of the caller (e.g. the cross-validation folds' factorizations) that share the
// probe's pool of threads: with Eigen's kernels on more than one thread, the factorization, the two eigenvalue
// iterations and each job are tasks of one thread each (a job must not rely on threads of its own); otherwise
// all run one after the other. An exception of any job or of the probe is rethrown once all have ended.
NormalEquationsProbe probe_normal_equations(const NormalEquations& ne, double rank_tolerance = -1.0,
                                            const DenseKernels* kernels = nullptr,
                                            const std::vector<std::function<void()>>& beside = {});

// Number of unknowns of the modes of total order N (general: M(M+1)/2, isotropic: isotropic_mode_count).
int sample_fit_unknowns(int order, bool isotropic);

// Peak bytes of a sample fit of `unknowns` modes whose normal equations are assembled per fold (folds = 0:
// one fit): (folds + kSampleFitSquares) unknowns x unknowns float64 matrices (the fold Grams, their sum, its
// factorizations and probes) and the design panels. Measured: 13-14 k^2 doubles of peak resident memory with
// 5 folds at k = 4,186 and 11,781 (general modes of order 12 and 16, 1,824 samples, 2026-11-29).
inline constexpr double kSampleFitSquares = 11.0;
inline constexpr double kSampleFitPanelBytes = 64e6;  // the design panels, about 4 million doubles twice
double sample_fit_bytes(int unknowns, int folds);
// ResourceError (before any allocation) when sample_fit_bytes exceeds the memory budget
// (icobrdf/core/support/memory_budget.hpp), naming the largest order of this class that fits.
void require_sample_fit_memory(int order, bool isotropic, int folds);

// The modes of a sample fit at the pairs (wi[s], wr[s]): samples x sample_fit_unknowns(order, isotropic), the
// isotropic modes (isotropic_modes_eval) or the general ones (helmholtz_modes_eval).
Eigen::MatrixXd sample_fit_modes(int order, bool isotropic, const RowMatrix3d& wi, const RowMatrix3d& wr);

// d_k of every unknown (see the header comment), in the library order of the chosen modes.
Eigen::VectorXd tikhonov_penalties(int order, bool isotropic, double power);

// Streaming accumulation: add() chunks of samples, then solve(). Memory O(unknowns^2).
class SampleFitAccumulator {
 public:
  // ArgumentError for an order outside [0, 16] (general modes: 9316 unknowns at 16; isotropic: up to 128),
  // channels not >= 1, lambda or p negative or not finite.
  SampleFitAccumulator(const SampleFitOptions& options, int channels);
  // wi, wr: rows x 3, values: rows x channels, weights: rows (finite, >= 0; rows with weight 0 are skipped).
  // ArgumentError on shape mismatch or non-finite values/weights.
  void add(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values, const Eigen::VectorXd& weights);
  // ArgumentError when no sample with positive weight was added.
  SampleFitResult solve() const;
  // With options.split over several parts: makes this process's factor (of its rows) the factor of every
  // process's rows, and the counts their sums (collective, see SampleFitSplit).
  void merge_parts();
  long long samples() const { return samples_; }
  int unknowns() const { return unknowns_; }

 private:
  void absorb(const Eigen::MatrixXd& block);
  SampleFitOptions options_;
  int channels_;
  int unknowns_;
  long long samples_ = 0;
  double weight_sum_ = 0.0;
  Eigen::MatrixXd r_;  // (unknowns + channels) square, upper triangular
};

// One-shot fit (fast path above, QR otherwise); weights empty means all 1. Same errors as the accumulator.
// With options.split (several parts) the fit passes over this process's part of the rows only (SampleFitSplit).
// `assembled`, when given, must be the normal equations of these samples (all rows, summed over the processes
// of a split) for these modes;
// `probed`, when given, probe_normal_equations(*assembled, options.rank_tolerance) (saves a factorization).
SampleFitResult fit_samples(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                            const Eigen::VectorXd& weights, const SampleFitOptions& options,
                            const NormalEquations* assembled = nullptr, const NormalEquationsProbe* probed = nullptr);

// The checks of the accumulator's constructor and add() (ArgumentError), for callers that work on the
// samples before fitting them.
void check_sample_fit_input(const SampleFitOptions& options, const RowMatrix3d& wi, const RowMatrix3d& wr,
                            const Eigen::MatrixXd& values, const Eigen::VectorXd& weights);

// The largest order accepted for the general (anisotropic) modes.
inline constexpr int kMaxSampleFitOrder = 16;

}  // namespace icobrdf
