#pragma once
// Kernel-driven fit of observations: the linear least-squares fit of the three weights of a Ross-Li model
// (icobrdf/core/models/kernel_models.hpp), the baseline of land remote sensing (MODIS MCD43; Lucht, Schaaf &
// Strahler 2000, IEEE TGRS 38(2), 977-998), beside the fit of the Koenderink-van Doorn modes
// (icobrdf/core/fit/sample_fit_selection.hpp) of the same samples.
//
// Data: S samples (w_i, w_r, f) with weights w_s >= 0 (the library's conventions: w_i towards the sun, f in 1/sr);
// the fit is of the BRF y = pi f, per channel:
//     minimize  sum_s w_s (y_s - K_s^T p)^2,   K_s = (1, K_vol(w_i, w_r), K_geo(w_i, w_r)),   p = (iso, vol, geo),
// solved by the SVD of W^(1/2) K (3 columns). The weights p are those of `model:ross-li:iso=..,vol=..,geo=..`.
// Weights of determination (Lucht & Lewis 2000, Int. J. Remote Sens. 21(1), 81-98): a quantity u = U^T p
// linear in the weights has the noise inflation 1/WoD = U^T (K^T W K)^-1 U, so its standard error is
// sigma sqrt(1/WoD), sigma the BRF noise of a sample of weight 1 (estimated as sqrt(RSS_w / (S - 3))). Reported
// for the white-sky albedo (U = (1, H_vol, H_geo)), the black-sky albedo at a solar zenith (U = (1, h_vol(sza),
// h_geo(sza))) and the nadir BRF at that zenith (U = (1, K_vol(sza, 0), K_geo(sza, 0))); the zenith is the
// weighted mean solar zenith of the samples.
// Kernel integrals: h_k(sza) = (1/pi) integral K_k(w_i, w_r) cos(vza) dOmega_r (black-sky), H_k = 2 integral_0^1
// h_k(mu) mu dmu (white-sky), by Gauss-Legendre quadrature (kKernelIntegralNodes): the MODIS ATBD's 0.189184
// (Ross-Thick) and -1.377622 (Li-Sparse-R) are reproduced to 1e-4 (the published Li-Sparse-R value differs from
// the integral of the published formula by 3.6e-5, tests/core/models/test_kernel_models.cpp;
// tests/core/fit/test_kernel_fit.cpp).
// Cross-validation: K folds dealt as the modes' folds (cross_validation_fold of the index among samples of
// positive weight), so both fits are scored on the same held-out samples; cv_rms is in 1/sr with the modes'
// definition (weighted mean square over held-out samples and channels). NaN when a fold's training samples do not
// determine the three weights. A fit whose weights the samples do not determine (condition of W^(1/2) K above
// kMaxDeterminedCondition) is reported with determined = false (minimum-norm weights, no error bars).
#include <Eigen/Core>

#include <string>
#include <vector>

#include "icobrdf/core/fit/sample_fit_selection.hpp"
#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/models/kernel_models.hpp"

namespace icobrdf {

// Gauss-Legendre nodes per dimension of the kernel integrals (cos(vza), raa in [0, pi], cos(sza)): the
// Li-Sparse-R kernel's kink along the edge of its overlap region limits the convergence; 96 nodes agree with
// 64 x 64 x 1024-node integrals to 1e-6 (tested against the ATBD to 1e-4).
inline constexpr int kKernelIntegralNodes = 96;

struct KernelChoice {
  VolumeKernel volume = VolumeKernel::RossThick;
  GeometricKernel geometric = GeometricKernel::LiSparseR;
};

// (1, K_vol, K_geo) at one pair.
Eigen::Vector3d kernel_row(const KernelChoice& kernels, const Eigen::Vector3d& wi, const Eigen::Vector3d& wr);
// (1, h_vol(sza), h_geo(sza)): the black-sky albedo vector at solar zenith `sza` [rad].
Eigen::Vector3d black_sky_kernel_integrals(const KernelChoice& kernels, double sza);
// (1, H_vol, H_geo): the white-sky albedo vector.
Eigen::Vector3d white_sky_kernel_integrals(const KernelChoice& kernels);

// One quantity u = U^T p of the fitted weights.
struct KernelQuantity {
  std::string name;          // "white-sky albedo", "black-sky albedo", "nadir BRF"
  Eigen::Vector3d u;         // U
  Eigen::VectorXd value;     // per channel
  double inflation = 0.0;    // 1/WoD = U^T (K^T W K)^-1 U
  Eigen::VectorXd sigma;     // per channel: noise_sigma sqrt(inflation) (NaN when S <= 3)
};

struct KernelFit {
  KernelChoice kernels;
  long long samples = 0;                  // samples of positive weight
  Eigen::MatrixXd weights;                // 3 x channels: iso, vol, geo (BRF)
  Eigen::Matrix3d inverse_gram;           // (K^T W K)^-1 (the pseudo-inverse when not determined)
  double condition = 0.0;                 // cond(W^(1/2) K)
  bool determined = false;                // condition <= kMaxDeterminedCondition
  Eigen::VectorXd noise_sigma;            // per channel, BRF of a sample of weight 1 (NaN when S <= 3)
  Eigen::VectorXd residual_rms;           // per channel, weighted, 1/sr
  double cv_rms = 0.0;                    // 1/sr, K-fold (NaN: a fold undetermined)
  int cv_folds = 0;
  double solar_zenith = 0.0;              // weighted mean solar zenith [rad] of the black-sky and nadir quantities
  std::vector<KernelQuantity> quantities; // white-sky albedo, black-sky albedo, nadir BRF
  // `ross-li:iso=..,vol=..,geo=..,volume=..,geometric=..` of one channel (a model spec).
  std::string spec(int channel) const;
};

// ArgumentError on shape mismatch, non-finite values or weights, no sample of positive weight, folds < 2.
KernelFit fit_kernel_weights(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                             const Eigen::VectorXd& weights, const KernelChoice& kernels = {},
                             int folds = kCrossValidationFolds);

// Which fit the held-out samples support: "kernels" when the kernel fit's CV RMS is within kCvTieFraction of the
// modes' (or below; the three-weight model wins ties), "modes" when the modes' is lower, "undecided" when either
// is NaN.
std::string supported_fit(double kernel_cv_rms, double modes_cv_rms);

}  // namespace icobrdf
