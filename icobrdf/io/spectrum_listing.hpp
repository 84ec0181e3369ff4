#pragma once
// A spectrum's coefficients as `icobrdf spectrum` lists them, with their mode indices: isotropic spectra give
// the IBSSS a_nm^l with [n, m, l] (icobrdf/core/basis/isotropic_modes.hpp), others the Helmholtz BSSS a_ab with
// [n, l, m, l'] (icobrdf/core/basis/helmholtz_modes.hpp), in those headers' order; and a sample fit's record
// (icobrdf/core/spectrum/spectrum.hpp SampleFitRecord) as JSON.
#include <nlohmann/json.hpp>

#include <string>

#include "icobrdf/core/spectrum/spectrum.hpp"

namespace icobrdf {

struct SpectrumListing {
  nlohmann::json indices;       // one index list per mode: [n, m, l] or [n, l, m, l']
  nlohmann::json coefficients;  // one list per channel, one value per mode (same order as indices)
  double asymmetry = 0.0;       // the largest coefficient_asymmetry over the channels (icobrdf/core/spectrum/spectrum_ops.hpp)
};

SpectrumListing list_spectrum(const Spectrum& s);

// Below this magnitude a coefficient is counted, not listed, in the text listing (unless every one is asked
// for): far under the accuracy of any grid projection (Gram errors are >= 1e-14) and of float32 storage.
inline constexpr double kListedCoefficientZero = 1e-14;

// One line per mode: "  [indices]" and per channel the coefficient (and "+- se", its standard error, when
// `standard_error` (channels x modes) is given); modes whose coefficients are all below kListedCoefficientZero
// are counted in a last line instead, unless `all`. `more` names how to list them ("--all lists them").
std::string spectrum_listing_text(const SpectrumListing& listing, const Eigen::MatrixXd* standard_error, bool all, const std::string& more);

// samples, unknowns, effective_rank, condition, residual_rms and noise_sigma (per channel, 1/sr), cv_rms (1/sr),
// cv_folds, tikhonov, tikhonov_power, order_choice, tikhonov_choice, fallback, solver, standard_errors (channels x
// unknowns).
nlohmann::json sample_fit_record_json(const SampleFitRecord& fit);

}  // namespace icobrdf
