#pragma once
// Automatic choices for fits of scattered samples (icobrdf/core/fit/sample_fit.hpp), and the checks that keep such a fit
// from failing silently.
//
// Order by K-fold cross-validation (cross_validate_order). The samples with positive weight are dealt into
// K folds by a hash of their index (deterministic, no random state). The weighted normal equations of each
// fold are assembled once at the largest candidate order; training on all folds but f uses
// G - G_f, b - b_f, and because the modes of order N are a prefix of those of order N_max (library order,
// icobrdf/core/basis/helmholtz_modes.hpp, icobrdf/core/basis/isotropic_modes.hpp) every candidate order is a leading block. The held-out
// weighted error of fold f is y_f^T W y_f - 2 x^T b_f + x^T G_f x, so one pass over the samples scores every
// order. (With single-precision Gram products, icobrdf/core/fit/sample_fit.hpp, the folds' solutions are refined
// and their held-out errors summed from the samples instead, in passes shared by all folds: held_out_pass.) An order is "determined" when every training Cholesky factor exists with
// cond(W^(1/2) A) <= kMaxDeterminedCondition (from Eigen's 1-norm estimate of cond(G)); undetermined orders
// are not candidates. Choice: the lowest determined order whose CV mean square is within kCvTieFraction of
// the smallest (mean squares closer than kCvResolution of the data's mean square counting as equal). The
// one-standard-error rule (Hastie, Tibshirani & Friedman, sec. 7.10) was tried first: on heavy-tailed data
// (a rough diffuser's grazing values) the fold-to-fold spread of 5 folds swamps real differences between
// orders and it chose order 1 (held-out error 0.34) where order 4 gives 0.27; the spread is still reported.
//
// Tikhonov strength by generalized cross-validation (choose_tikhonov_gcv; Golub, Heath & Wahba,
// Technometrics 21, 1979): GCV(lambda) = S RSS(lambda) / (S - tr H(lambda))^2 summed over channels. The
// unpenalized modes (d_k = 0) are eliminated (Schur complement), the penalized ones scaled by d^(-1/2); one
// symmetric eigendecomposition of the reduced k x k matrix then gives RSS and tr H for every lambda in O(k).
// lambda runs over kGcvPoints values log-spaced in [1e-14, 1e2] times the largest eigenvalue.
//
// The checked fit (fit_samples_checked) runs five steps:
//   1. the model class and the order: the given ones, or (SampleFitPlan::choose_order) the order chosen by K-fold
//      cross-validation over the orders from 0 up to the largest with kMinSamplesPerUnknown training samples per
//      unknown (and at most SampleFitPlan::max_order, or kMaxAutoOrderGeneral / kMaxAutoOrderIsotropic when that is
//      not given), and with SampleFitPlan::choose_class the class too: the isotropic and the general modes are each
//      scored over their orders on the same folds (the fold of a sample is a hash of its index), and the chosen
//      (class, order) is the one with the fewest unknowns among the determined candidates of both classes whose CV
//      mean square is within kCvTieFraction of the smallest (the isotropic modes on a tie of unknowns: at order 0
//      they are the same constant). So data that cannot determine the general modes beyond order 0 (in-plane
//      samples, a single plane of incidence) end isotropic whenever an isotropic order predicts the held-out
//      samples better, and the CV RMS of both classes is reported.
//   2. lambda: the given one, or (SampleFitPlan::choose_tikhonov) the one chosen by GCV.
//   3. the fit and its determinacy: a fit with unseen modes, a null space, or condition > kMaxDeterminedCondition
//      (lambda = 0) does not determine its modes. General (anisotropic) modes fall back to the isotropic modes of
//      the same order (in-plane data, for one, see only isotropic combinations); if those are not determined
//      either, to the isotropic modes with Tikhonov regularization, lambda by GCV. The fallback is a note.
//   4. scale: the fit is evaluated at kScaleCheckDirections^2 direction pairs covering the whole domain
//      (a Fibonacci lattice of the hemisphere, every pair); if |f| anywhere exceeds kScaleGuardFactor times
//      the largest |sample|, the samples do not bound it where they do not lie. Regularization instead of
//      refusal: the fit is then Tikhonov-regularized (penalty d_k of sample_fit.hpp, power as given) with a
//      lambda of the GCV grid found by bisection (larger lambdas shrink the fit towards its unpenalized part,
//      which the samples' mean bounds): with lambda chosen by GCV, the GCV-best bounded one (the smallest
//      bounded lambda at or above GCV's: GCV rises away from its minimum); with lambda given (0: the plain
//      least squares asked for), the smallest bounded lambda above it, the least departure from the request
//      ("smallest bounding lambda"; on CURET at order 8 the GCV-best bounded lambda pushes one more material
//      over 10% relative RMS than plain least squares). The note reports the |f| avoided, lambda (and GCV's),
//      the condition and the effective degrees of freedom tr H. Only when no lambda bounds the fit is it
//      refused (UnsupportedError, one line), and then only when the order was given: a cross-validated order that
//      cannot be bounded is chosen again among the lower orders (order 0, the samples' weighted mean, is bounded).
//   5. the CV error of the final configuration (the same folds) is recorded.
// Split over processes (SampleFitPlan::options.split, icobrdf/core/fit/sample_fit.hpp SampleFitSplit): the folds
// keep their hash of the sample's index among all samples; each process assembles the folds' normal
// equations of its rows and one sum gives every fold's, and each held-out pass is summed the same way, so
// every choice (order, lambda, fallback) is made from the same figures on every process.
#include <Eigen/Core>

#include <limits>
#include <string>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/fit/sample_fit.hpp"

namespace icobrdf {

// K of K-fold cross-validation: 5, one of the two values Hastie, Tibshirani & Friedman recommend (The Elements of
// Statistical Learning, 2nd ed., sec. 7.10.1: 5 or 10); each fold trains on 4/5 of the samples, one factorization each.
inline constexpr int kCrossValidationFolds = 5;
// A fit whose kept part has condition above this amplifies data errors a million-fold: its modes are not
// determined by the samples (the same bound keeps the normal equations accurate, icobrdf/core/fit/sample_fit.hpp).
inline constexpr double kMaxDeterminedCondition = kNormalEquationsMaxCondition;
// Held-out mean squares differing by less than this fraction of the data's mean square are equal: the
// expanded form y^T W y - 2 x^T b + x^T G x cancels to about unknowns * 1e-16 of y^T W y.
inline constexpr double kCvResolution = 1e-10;
// CV mean squares within this fraction of the best are ties, won by the lower order: a correct model with
// dp more unknowns than needed exceeds the true order's mean square by about dp / n of the noise variance
// (0.2% for 6 extra unknowns and 3,200 held-out samples), more than the 0.1% fold-sampling noise of such
// a difference, so larger models do not win by noise; a missing mode costs far more.
inline constexpr double kCvTieFraction = 0.005;
// Candidate orders need at least this many training samples per unknown.
inline constexpr int kMinSamplesPerUnknown = 2;
// Largest orders tried when none is given: general modes 8 (1035 unknowns), isotropic 20 (506).
inline constexpr int kMaxAutoOrderGeneral = 8;
inline constexpr int kMaxAutoOrderIsotropic = 20;
// 10 lambdas per decade over the 16 decades [1e-14, 1e2] (and both ends): neighbours 10^0.1 = 1.26x apart, and
// each point costs O(unknowns) once the reduced matrix's eigendecomposition is known.
inline constexpr int kGcvPoints = 161;
// One order of magnitude: a least-squares fit that the samples bound stays near their range (a Gibbs
// overshoot is ~9%); beyond 10 times the largest sample the fit is extrapolating.
inline constexpr double kScaleGuardFactor = 10.0;
// Directions of the hemisphere lattice of the scale check (its pairs: 48^2 = 2,304): 2 pi / 48 sr each, so
// neighbours lie about 21 degrees apart, the half-period of the order-8 modes (kMaxAutoOrderGeneral).
inline constexpr int kScaleCheckDirections = 48;

struct OrderCrossValidation {
  int folds = 0;
  std::vector<int> orders;          // candidates, ascending
  std::vector<double> rms;          // CV root mean square error per order [1/sr] (NaN: undetermined)
  std::vector<double> rms_se;       // its standard error over folds (delta method) [1/sr]
  std::vector<bool> determined;
  int chosen = -1;                  // -1 when no order is determined
};

// Fold of each sample (0 .. folds-1), by a hash of the index.
int cross_validation_fold(long long index, int folds);

// Scores the orders min_order..max_order (ArgumentError when empty or beyond the modes' range) with
// `tikhonov` (lambda, power) fixed.
OrderCrossValidation cross_validate_order(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                                          const Eigen::VectorXd& weights, bool isotropic, int min_order, int max_order,
                                          double tikhonov, double tikhonov_power, int folds = kCrossValidationFolds,
                                          const FitProgress& progress = {});

struct GcvChoice {
  double lambda = 0.0;
  double score = 0.0;
  std::vector<double> lambdas, scores;
};
// GCV over lambda for the modes of (order, isotropic) given their normal equations.
GcvChoice choose_tikhonov_gcv(const NormalEquations& ne, int order, bool isotropic, double tikhonov_power);

struct SampleFitPlan {
  SampleFitOptions options;        // order, modes, lambda, power, rank tolerance, progress
  bool choose_order = false;       // cross-validate the order (options.order ignored)
  // With choose_order: cross-validate the isotropic against the general modes, each over its orders, on the
  // same folds (options.isotropic ignored; see "Model class" above).
  bool choose_class = false;
  bool choose_tikhonov = false;    // GCV for lambda (options.tikhonov ignored)
  int max_order = -1;              // largest candidate; < 0: the kMaxAutoOrder* bound
  int folds = kCrossValidationFolds;
};

struct CheckedSampleFit {
  SampleFitResult fit;
  OrderCrossValidation order_cv;   // filled when the order was chosen (the chosen class's)
  // Filled when the class was chosen: each class's orders, and the CV RMS of each class's own choice [1/sr]
  // (NaN when none of its orders is determined).
  OrderCrossValidation isotropic_cv, general_cv;
  double cv_rms_isotropic = std::numeric_limits<double>::quiet_NaN();
  double cv_rms_general = std::numeric_limits<double>::quiet_NaN();
  std::string class_choice = "given";     // "given" or "cross-validation"
  // Set when the fit of the chosen or given order was not bounded by the samples and was regularized instead
  // (see "Regularization instead of refusal").
  bool regularized_for_bound = false;
  double unregularized_max_abs_fit = 0.0;  // |f| the unregularized fit reached [1/sr] (when regularized_for_bound)
  double cv_rms = 0.0;             // CV error of the final fit [1/sr]; NaN when a fold cannot be fitted
  int cv_folds = 0;
  std::string order_choice = "given";     // "given" or "cross-validation"
  std::string tikhonov_choice = "given";  // "given", "generalized cross-validation"
  std::string fallback;                   // empty, or what replaced the requested fit and why
  std::vector<std::string> notes;         // one line each, for the report
  double max_abs_fit = 0.0;               // largest |f| of the fit over the scale-check pairs [1/sr]
  double max_abs_sample = 0.0;            // largest |sample| [1/sr]
};

// The requested fit with the choices and checks above. With choose_order it never refuses: samples that determine
// no order in every fold get the isotropic order 0 (their weighted mean), and an order the scale check cannot bound
// is chosen again below it. UnsupportedError (one line) only for a given order that no lambda bounds;
// ArgumentError as fit_samples.
CheckedSampleFit fit_samples_checked(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                                     const Eigen::VectorXd& weights, const SampleFitPlan& plan);

}  // namespace icobrdf
