#pragma once
// The figures `icobrdf fit` reports of one fit (fit_source, icobrdf/pipeline/fit_source.hpp) as JSON: the
// spectrum's size and quality figures (Gram error and condition, reciprocity violation, anisotropic energy,
// largest directional albedo), and for a least-squares fit of scattered samples (MERL tables, CSV samples)
// the figures of that fit (rank, condition, choices of order and Tikhonov lambda, residual RMS in 1/sr), so
// that rank-deficient data is visible. A fit without the tessellation (samples, stored coefficients) has no
// Gram figures: its level is the one asked for, and "grid_use" says the grid served the albedo figure only.
#include <nlohmann/json.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "icobrdf/core/fit/kernel_fit.hpp"
#include "icobrdf/core/fit/sample_fit_selection.hpp"
#include "icobrdf/io/sample_csv.hpp"
#include "icobrdf/pipeline/fit_source.hpp"

namespace icobrdf {

// What one fit reports. The caller fills every field: the fit, what the SOURCE kept of it (for a measured
// SOURCE, icobrdf/io/measured_sources.hpp: last_checked_sample_fit, merl_missing_samples), and the request.
struct FitReport {
  const FitResult* fit = nullptr;
  const CheckedSampleFit* checked = nullptr;  // the sample fit of a measured SOURCE; null for other fits
  const KernelFit* kernels = nullptr;         // the kernel-driven fit of the same samples (CSV); null for other fits
  std::int64_t missing_samples = -1;          // masked samples of a MERL table (all channels); -1 for other sources
  std::string output;                         // the spectrum file written
  int level_asked = 0;                        // the tessellation level asked for
  GridKind grid_kind = GridKind::EqualArea;   // the tessellation asked for
  double seconds = 0.0;                       // wall time of the whole command
  std::string dense_kernels = "none";         // the kernels that solved the normal equations ("none" when none ran)
  int ranks = 1;                              // processes of an mpirun job that fitted it
  // The samples of a CSV or CURET SOURCE (icobrdf/io/measured_sources.hpp samples_of); null for other fits. Their
  // exchanged pairs give the data's own non-reciprocal fraction (icobrdf/pipeline/exchanged_pairs.hpp, metric
  // "f", pairs within kSwapToleranceDeg), reported beside the fit's relative residual.
  const BrdfSamples* samples = nullptr;

  // The tessellation took part in the fit (not samples or stored coefficients).
  bool grid_fit() const { return fit->spectrum.level >= 0; }
};

// The JSON: source, output, order, modes, level (the one asked for when !grid_fit), grid, cells, channels,
// isotropic, cosine, filter, gram_error and gram_condition (grid fits only), grid_use (other fits),
// reciprocity_violation, anisotropy_fraction, max_albedo, seconds; "sample_fit" (samples, unknowns,
// effective_rank, null_space_dimension, unseen_modes, rank_threshold, condition_of_kept_part, solver,
// dense_kernels, tikhonov, tikhonov_choice, order_choice, cv_rms, cv_folds, fallback, notes, noise_sigma,
// residual_rms) for sample fits; "kernel_fit" (kernels, weights per channel as iso/vol/geo and model spec,
// condition, determined, noise_sigma and residual_rms, cv_rms, solar_zenith_deg, quantities with value, sigma
// and inflation = 1/WoD, supported: kernels|modes|undecided) beside it; missing_samples for MERL tables;
// "data_asymmetry" (exchanged_samples, tolerance_deg, asymmetry, median_relative_difference,
// relative_residual) for samples.
nlohmann::json fit_report_json(const FitReport& report);

// A report of `fit` of `source` with what the SOURCE kept of it filled in (icobrdf/io/measured_sources.hpp:
// last_checked_sample_fit, last_kernel_fit, merl_missing_samples); the samples (samples_of, which pipeline/
// does not ask) and the request's fields are the caller's. `source` must outlive the report.
FitReport fit_report_of(const FitResult& fit, const BrdfSource& source);
// The split of a fit over the `ranks` processes of an mpirun job added to its JSON: ranks, split ("operators
// by rows" when the ranks exchanged operator rows, "samples" when they summed passes over samples, else
// "none") and peak_rss_bytes_per_rank.
void add_rank_split_json(nlohmann::json& j, int ranks, int exchanges, int sample_sums, const std::vector<double>& peak_rss_per_rank);

// The same as lines of text: what was fitted on which grid, the quality figures, the sample fit's figures
// and choices (with a warning when the samples leave modes undetermined), the kernel-driven fit beside it and
// which of the two the held-out samples support, the masked MERL samples.
std::string fit_report_text(const FitReport& report);

}  // namespace icobrdf
