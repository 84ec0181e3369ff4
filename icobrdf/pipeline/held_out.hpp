#pragma once
// The direction pairs a material's errors are measured on, and the errors of a spectrum there.
//
// Held-out pairs are never used in fitting: every light x camera pair when the scene gives both, else
// `holdout_pairs` pairs uniform in solid angle (incident directions within the material's incidence range),
// seeded by the material's name so that a build is reproducible. The reference values f come from the
// source itself. Sources judged at their own samples are split instead (BrdfSource::own_held_out, drawn in
// icobrdf/io/measured_sources.cpp), and their representations are fitted on the rest (HeldOutSplit::training):
//   * a MERL table (no lights x cameras given): `holdout_pairs` of its own samples, drawn by their solid-angle
//     measure (measured_sources.cpp), since its lookup between samples is a step function; every bin drawn is
//     missing from the training table;
//   * CSV samples: held_out_sample_count of the samples whose incidence is in the range, those with the
//     smallest splitmix64(S + INDEX) (icobrdf/core/support/scramble.hpp), S the FNV-1a hash of "holdout|NAME" read as
//     a 64-bit integer, INDEX the sample's position after duplicates are merged (deterministic, no random
//     state, spread over the file whatever its order); the fits use all others. A merged sample counts as one pair per
//     row it merged. Lights x cameras are refused (ArgumentError): samples have no value there.
//
// Reciprocity (icobrdf/io/scene.hpp): for a source not reciprocal by construction
// (BrdfSource::reciprocal_by_construction) the data's asymmetry is measured over the held-out pairs,
//   asymmetry = |w (f - (f + f^T)/2)| / |w f|,   f^T the values with w_i and w_r exchanged,
// and with the material's `reciprocal` (the default) the reference f becomes (f + f^T)/2:
//   * a source with values everywhere (an RGL material, SCATMECH coefficients): f^T is the source evaluated at
//     the exchanged pairs;
//   * a source judged at its own samples (CSV samples): f^T exists only where two held-out samples are each
//     other's exchange, both directions within kSwapToleranceDeg; the asymmetry is measured over those pairs
//     (NaN when there are none: not measurable), their reference becomes (f + f^T)/2 and every other
//     sample keeps its raw value (nothing better is known there).
// A source reciprocal by construction (models that say so, MERL tables, spectra) has asymmetry 0.
//
// Noise: for a source with values on a grid of its own (BrdfSource::noise_sigma_at: RGL value tables, MERL
// tables) the data's noise figure is, over the held-out pairs and channels,
//   noise = |w sigma| / |w f|,   sigma the standard deviation of independent noise at each pair
// (icobrdf/core/tables/grid_noise.hpp), f the source's own values: the relative L2 of the noise on the data's
// values in the error's metric, i.e. the error the noise-free BRDF itself would have against the raw values at the
// data's nodes. The held-out reference has less: it interpolates between nodes (a bilinear blend keeps 1/4 to 1
// of a node's variance) and, judged against the reciprocal part, averages two values (1/2), so its own noise is
// about 0.35-0.7 of the figure. NaN when the source has no grid (analytic models, scattered samples).
//
// Errors are measured on w f with w = 1 (metric "f") or w = cos(theta_i) cos(theta_r) (metric "cosine": the
// projected solid angle, i.e. the reflected radiance per unit irradiance as a renderer integrates it, which
// does not let the grazing growth of microfacet BRDFs dominate):
//   relative L2  = |w (f_fit - f)| / |w f|           over all pairs and channels
//   relative max = max |w (f_fit - f)| / max |w f|
#include <Eigen/Core>

#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/scene.hpp"

namespace icobrdf {

using HeldOutPairs = PairValues;  // f: pairs x channels

// Two held-out samples are each other's exchange when w_i of one and w_r of the other (and the reverse) are
// within this angle: a goniometer's angular resolution (0.1-0.5 degrees) with a margin for the rounding of
// angles written in a CSV file.
inline constexpr double kSwapToleranceDeg = 1.0;

struct HeldOutSplit {
  HeldOutPairs pairs;
  std::unique_ptr<BrdfSource> training;  // the source without the held-out samples; nullptr: the source itself
  double asymmetry = 0.0;           // the data's own, as above (NaN: not measurable)
  double noise = std::numeric_limits<double>::quiet_NaN();  // the data's noise figure, as above (NaN: not available)
  bool reciprocal_reference = false;  // pairs.f is the reciprocal part of the source's values
};

// InputError when the source gives a non-finite value at a pair, or has too few samples to split (fewer
// than kHeldOutShare, or none in the incidence range).
HeldOutSplit held_out_split(const Scene& scene, const SceneMaterial& material, const BrdfSource& source);
// The noise figure above at any pairs: |w sigma| / |w f| over rows and channels, sigma = source.noise_sigma_at(pairs),
// f the source's values there (pairs.f), w the metric's weights per pair; NaN when the source has no grid or
// |w f| = 0.
double noise_figure(const BrdfSource& source, const PairValues& pairs, const Eigen::VectorXd& w);
// The pairs alone.
HeldOutPairs held_out_pairs(const Scene& scene, const SceneMaterial& material, const BrdfSource& source);

struct HeldOutError {
  double l2 = 0.0;   // relative L2
  double max = 0.0;  // relative max
};

// The errors of spectra of order <= max_order against held-out pairs, with the basis values at the pairs
// computed once.
// A pair is grazing when theta_i or theta_r exceeds kGrazingDeg: there cos theta < 0.17, and the "f" metric
// weighs values a renderer scales by less than a sixth.
inline constexpr double kGrazingDeg = 80.0;
class HeldOutErrors {
 public:
  // reciprocal_reference: the pairs' f is the reciprocal part of the source's values (HeldOutSplit).
  HeldOutErrors(const HeldOutPairs& pairs, int max_order, ErrorMetric metric, bool reciprocal_reference = false);
  // `channels`: one coefficient matrix per channel; only its leading block of `order` is used.
  HeldOutError operator()(const std::vector<Eigen::MatrixXd>& channels, int order) const;
  // The values sum_ab C_ab K_a(w_i) K_b(w_r) of such a spectrum at the pairs: pairs x channels.
  Eigen::MatrixXd modes_values(const std::vector<Eigen::MatrixXd>& channels, int order) const;
  // The errors of fitted values f_fit (pairs x channels) of any representation.
  HeldOutError of_values(const Eigen::MatrixXd& fit) const;
  const HeldOutPairs& pairs() const { return *pairs_; }
  const Eigen::VectorXd& weights() const { return w_; }  // the metric's w per pair
  // The reference at other pairs, made as the held-out one was: the source's values, or their reciprocal part.
  Eigen::MatrixXd reference_at(const BrdfSource& source, const RowMatrix3d& wi, const RowMatrix3d& wr) const;
  // Share of the squared reference norm sum w^2 f^2 from grazing pairs (kGrazingDeg); 0 when the norm is 0.
  double grazing_share() const { return grazing_share_; }

 private:
  Eigen::MatrixXd ki_, kr_;  // pairs x modes of max_order
  const HeldOutPairs* pairs_;
  Eigen::VectorXd w_;        // pairs
  double ref_norm_ = 0.0, ref_max_ = 0.0;
  double grazing_share_ = 0.0;
  bool reciprocal_reference_ = false;
};

// The leading block of each channel for `order` (the spectrum's truncation).
std::vector<Eigen::MatrixXd> truncate_channels(const std::vector<Eigen::MatrixXd>& channels, int order);

}  // namespace icobrdf
