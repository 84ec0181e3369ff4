#include "icobrdf/io/spectrum_listing.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"

namespace icobrdf {

SpectrumListing list_spectrum(const Spectrum& s) {
  SpectrumListing out{nlohmann::json::array(), nlohmann::json::array(), 0.0};
  for (const auto& c : s.channels) out.asymmetry = std::max(out.asymmetry, coefficient_asymmetry(c));
  if (s.isotropic) {
    for (const auto& m : isotropic_modes(s.order)) out.indices.push_back({m.n, m.m, m.l});
    for (const auto& c : s.channels) {
      const Eigen::VectorXd v = ibsss_from_coefficients(c);
      out.coefficients.push_back(std::vector<double>(v.data(), v.data() + v.size()));
    }
  } else {
    for (const auto& m : helmholtz_modes(s.order)) out.indices.push_back({m.n, m.l, m.m, m.lp});
    for (const auto& c : s.channels) {
      const Eigen::VectorXd v = bsss_from_coefficients(c);
      out.coefficients.push_back(std::vector<double>(v.data(), v.data() + v.size()));
    }
  }
  return out;
}

std::string spectrum_listing_text(const SpectrumListing& listing, const Eigen::MatrixXd* standard_error, bool all, const std::string& more) {
  const nlohmann::json& indices = listing.indices;
  const nlohmann::json& coefficients = listing.coefficients;
  std::string out;
  size_t zeros = 0;
  for (size_t k = 0; k < indices.size(); ++k) {
    bool all_zero = true;
    for (const auto& ch : coefficients) all_zero = all_zero && std::abs(ch[k].get<double>()) < kListedCoefficientZero;
    if (all_zero && !all) {
      ++zeros;
      continue;
    }
    std::string line = "  " + indices[k].dump();
    for (size_t c = 0; c < coefficients.size(); ++c) {
      line += fmt::format("  {: .10e}", coefficients[c][k].get<double>());
      if (standard_error) line += fmt::format(" +- {:.3e}", (*standard_error)(static_cast<Eigen::Index>(c), static_cast<Eigen::Index>(k)));
    }
    out += line + "\n";
  }
  if (zeros) out += fmt::format("  ({} coefficients below {:.0e} not listed; {})\n", zeros, kListedCoefficientZero, more);
  return out;
}

nlohmann::json sample_fit_record_json(const SampleFitRecord& fit) {
  nlohmann::json se = nlohmann::json::array();
  for (Eigen::Index c = 0; c < fit.standard_error.rows(); ++c) {
    std::vector<double> row(static_cast<size_t>(fit.standard_error.cols()));
    for (Eigen::Index k = 0; k < fit.standard_error.cols(); ++k) row[static_cast<size_t>(k)] = fit.standard_error(c, k);
    se.push_back(row);
  }
  return {{"samples", fit.samples},       {"unknowns", fit.unknowns},
          {"effective_rank", fit.effective_rank}, {"condition", fit.condition},
          {"residual_rms", fit.residual_rms}, {"noise_sigma", fit.noise_sigma},
          {"cv_rms", fit.cv_rms},         {"cv_folds", fit.cv_folds},
          {"tikhonov", fit.tikhonov},     {"tikhonov_power", fit.tikhonov_power},
          {"order_choice", fit.order_choice}, {"tikhonov_choice", fit.tikhonov_choice},
          {"fallback", fit.fallback},     {"solver", fit.solver},
          {"effective_dof", fit.effective_dof}, {"class_choice", fit.class_choice},
          {"cv_rms_isotropic", fit.cv_rms_isotropic}, {"cv_rms_general", fit.cv_rms_general},
          {"standard_errors", se}};
}

}  // namespace icobrdf
