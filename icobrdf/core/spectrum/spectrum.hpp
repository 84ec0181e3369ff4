#pragma once
// Spectrum: the coefficients of a BRDF in the hemisphere basis K (icobrdf/core/basis/hemisphere_basis.hpp).
//
// For a BRDF f (or g = f cos theta_i when `cosine`), channel c holds the symmetric M x M matrix
//   C_ab = integral integral f(w_i, w_r) K_a(w_i) K_b(w_r) dOmega_i dOmega_r,   a, b < M = (N+1)(N+2)/2,
// with K indexed by the ANSI single index j = (n(n+2)+l)/2. Helmholtz reciprocity <=> C symmetric.
// f is then approximated by sum_ab C_ab K_a(w_i) K_b(w_r) [1/sr].
// The Helmholtz (BSSS) coefficient vector and the isotropic (IBSSS) vector are views of C
// (icobrdf/core/basis/helmholtz_modes.hpp, icobrdf/core/basis/isotropic_modes.hpp).
#include <Eigen/Core>

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace icobrdf {

// How a spectrum was fitted to scattered samples (icobrdf/core/fit/sample_fit.hpp, icobrdf/core/fit/sample_fit_selection.hpp):
// stored with it (docs/file-format.md, group sample_fit) and printed by `icobrdf spectrum`.
struct SampleFitRecord {
  long long samples = 0;                 // samples used (weight > 0)
  int unknowns = 0;                      // modes fitted
  int effective_rank = 0;
  double condition = std::numeric_limits<double>::quiet_NaN();  // of W^(1/2) A on the kept part
  std::vector<double> residual_rms;      // per channel, weighted [1/sr]
  std::vector<double> noise_sigma;       // per channel, sigma of a weight-1 sample [1/sr]
  double cv_rms = std::numeric_limits<double>::quiet_NaN();  // K-fold CV error of the final fit [1/sr]
  int cv_folds = 0;
  double tikhonov = 0.0;                 // lambda
  double tikhonov_power = 1.0;           // p
  std::string order_choice;              // "given" or "cross-validation"
  std::string tikhonov_choice;           // "given" or "generalized cross-validation"
  std::string fallback;                  // empty, or the fallback taken and why
  std::string solver;                    // "normal equations" or "QR"
  double effective_dof = std::numeric_limits<double>::quiet_NaN();  // tr H: effective number of parameters
  std::string class_choice;              // "given" or "cross-validation" (isotropic against general modes)
  // CV RMS of each class's own order choice when the class was chosen [1/sr]; NaN otherwise.
  double cv_rms_isotropic = std::numeric_limits<double>::quiet_NaN();
  double cv_rms_general = std::numeric_limits<double>::quiet_NaN();
  // channels x unknowns: standard error of each mode coefficient, library order of the spectrum's modes
  // (BSSS, or IBSSS when the spectrum is isotropic); NaN where undefined.
  Eigen::MatrixXd standard_error;
};

struct Spectrum {
  int order = 0;                          // total order N of the K basis
  bool isotropic = false;                 // C lies in the isotropic subspace (projected onto it)
  bool cosine = false;                    // coefficients of g = f cos(theta_i) instead of f
  std::vector<Eigen::MatrixXd> channels;  // one M x M symmetric matrix per channel (1 or 3)
  std::string source;                     // canonical SOURCE string it came from
  // Names of the channels ("r", "g", "b"; "550nm"), one per channel, or empty when the source names none.
  std::vector<std::string> channel_names;
  std::string filter = "none";            // low-pass filter applied to it (none = plain truncation)
  int level = -1;                         // tessellation level used; -1 when computed without a grid
  std::string grid_kind;                  // "equal-area", "geodesic", ... ; empty when no grid
  // Figures of merit recorded with the spectrum; NaN when not measured.
  double gram_error = std::numeric_limits<double>::quiet_NaN();             // max |G - I| of the grid basis
  double reciprocity_violation = std::numeric_limits<double>::quiet_NaN();  // ||F - F^T|| / ||F|| of the input
  double anisotropy_fraction = std::numeric_limits<double>::quiet_NaN();    // anisotropic energy / total
  double max_albedo = std::numeric_limits<double>::quiet_NaN();             // white-furnace figure
  std::optional<SampleFitRecord> sample_fit;  // present for fits of scattered samples

  int modes() const { return (order + 1) * (order + 2) / 2; }
  int channel_count() const { return static_cast<int>(channels.size()); }
};

}  // namespace icobrdf
