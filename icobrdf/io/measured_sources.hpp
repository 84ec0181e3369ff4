#pragma once
// SOURCE kinds for measured data (icobrdf/io/brdf_source.hpp's open_source dispatches to open_measured_source):
//
//   FILE.binary | merl:FILE                       MERL table (icobrdf/io/merl.hpp), 3 channels
//   FILE.bsdf[#lambda=NM[/NM/NM]] | rgl:FILE[...]  RGL material (icobrdf/io/rgl_bsdf.hpp): RGB files give 3 channels
//                                                 (r, g, b); spectral files one channel per wavelength of the
//                                                 file, or the 1-3 wavelengths chosen (interpolated) by lambda
//   FILE.csv[#OPTIONS] | samples:FILE[#OPTIONS]   BRDF samples (icobrdf/io/sample_csv.hpp); OPTIONS, comma-separated:
//                                                 radians, strict, tikhonov=LAMBDA|auto, power=P, rank-tol=T,
//                                                 values=brf|brdf, columns=NAME/NAME/... (icobrdf/io/angle_columns.hpp)
//   curet:ABRDF.DAT#sample=N[,table=FILE][,...]    one sample (material) of the CURET database (icobrdf/io/curet.hpp):
//                                                 205 samples, one channel; the geometry table is table.txt beside
//                                                 ABRDF.DAT unless table= names it; fit options as for CSV samples
//   FILE.zernike.csv[#OPTIONS] | scatmech:FILE[#OPTIONS] | any other FILE whose content is one
//                                                 (icobrdf/io/scatmech_coefficients.hpp looks_like_scatmech_coefficients)
//                                                 SCATMECH Zernike-expansion coefficients
//                                                 (icobrdf/io/scatmech_coefficients.hpp); OPTIONS: lambda=UM, scale=R
//
// Fitting (fit()):
//   * MERL: the table's valid nodes are scattered samples (icobrdf/io/merl.hpp merl_samples: node directions, bin
//     solid-angle weights; nodes with a missing channel or a direction below the horizon are excluded),
//     fitted by weighted least squares (icobrdf/core/fit/sample_fit.hpp) on the isotropic modes of the requested order
//     (a MERL table holds only isotropic BRDFs, so the spectrum is isotropic whatever --isotropic says).
//     The grid of the context is not used for the fit (only for the max-albedo figure); the LUT sampling
//     and projection kind do not apply.
//   * CSV and CURET samples: weighted least squares of the samples (weights = duplicate counts) on the Helmholtz
//     modes, or the isotropic modes with --isotropic, with the Tikhonov options above, through the checked
//     fit of icobrdf/core/fit/sample_fit_selection.hpp: order kChooseOrder = chosen by K-fold cross-validation (with
//     lambda by GCV unless tikhonov=LAMBDA is given), tikhonov=auto = lambda by GCV, fallbacks when the
//     samples do not determine the modes, UnsupportedError when the fit is not bounded by the samples.
//     The grid is likewise unused except for the max-albedo figure. The spectrum carries the fit's record
//     (Spectrum::sample_fit: standard errors, CV error, rank, condition, residual).
//   * SCATMECH: the file's isotropic spectrum truncated or zero-padded to the requested order (exact, no grid).
//   * RGL: like an analytic model (icobrdf/core/fit/spectral_fit.hpp fit_model: f sampled on the context's grid, not
//     reciprocal, not assumed isotropic); 1 or 3 channels only (a spectral file needs #lambda).
//   MERL, CSV and SCATMECH refuse --cosine (UnsupportedError): their expansions are of f; a low-pass filter applies after the fit.
// notes(): SCATMECH sources count the polarized rows (Mueller elements other than 11) and the k != l rows.
// Evaluation (eval()): RGL as icobrdf/io/rgl_bsdf.hpp describes; MERL looks the table up (NaN at missing samples); SCATMECH evaluates its spectrum
// at its own order; CSV samples throw ArgumentError (the samples must be fitted first; a bank fits them, split
// into training and held-out samples by icobrdf/pipeline/held_out.hpp).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/core/fit/kernel_fit.hpp"
#include "icobrdf/core/fit/sample_fit.hpp"
#include "icobrdf/core/fit/sample_fit_selection.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/merl.hpp"
#include "icobrdf/io/sample_csv.hpp"

namespace icobrdf {

// nullptr when `text` names none of the kinds above; otherwise the opened source (errors as documented
// in the readers: InputError for bad files, ArgumentError for bad options).
std::unique_ptr<BrdfSource> open_measured_source(const std::string& text);

// Figures of the last sample fit of a MERL or CSV source (for reports): nullptr for other sources or
// before fit() was called.
const SampleFitResult* last_sample_fit(const BrdfSource& source);
// The same with the choices, fallback and notes of the checked fit (CSV; MERL: the plain fit).
const CheckedSampleFit* last_checked_sample_fit(const BrdfSource& source);
// The kernel-driven fit (icobrdf/core/fit/kernel_fit.hpp) of the samples of a CSV source, made beside its last
// fit of the modes on the same folds; nullptr for other sources or before fit() was called.
const KernelFit* last_kernel_fit(const BrdfSource& source);
// True for the sources that accept FitOptions::order = kChooseOrder (CSV samples).
bool chooses_order(const BrdfSource& source);

// What the sources hold of their own, for reports and tests (the bank builder asks BrdfSource instead:
// values_only_at_samples, own_held_out, largest_sample_order, own_half_angle_nodes; the CSV and MERL sources
// answer them, icobrdf/pipeline/held_out.hpp describes their held-out draws):
// the samples of a CSV source (nullptr for other sources; such a source has no value between its samples);
const BrdfSamples* samples_of(const BrdfSource& source);
// the CSV source fitted on the samples whose `held_out` entry is false (same text and options; size of
// held_out = samples), ArgumentError when none is left;
std::unique_ptr<BrdfSource> samples_source_without(const BrdfSource& source, const std::vector<bool>& held_out);
// the MERL source whose table has the bins `held_out` (MerlBin::flat) missing: its fits leave them out and its
// lookup there is NaN.
std::unique_ptr<BrdfSource> merl_source_without(const BrdfSource& source, const std::vector<std::int64_t>& held_out);
// (BrdfSource::largest_sample_order of these sources: at least kMinSamplesPerUnknown samples per unknown, at
// most the kMaxAutoOrder* bound of icobrdf/core/fit/sample_fit_selection.hpp; MERL tables only isotropic ones.)

// Missing samples (all channels) of a MERL source's table; -1 for other sources.
std::int64_t merl_missing_samples(const BrdfSource& source);
// The table of a MERL SOURCE; nullptr for any other source.
const MerlTable* merl_table_of(const BrdfSource& source);

}  // namespace icobrdf
