#include "icobrdf/pipeline/fit_report.hpp"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "icobrdf/core/basis/antisymmetric_modes.hpp"
#include "icobrdf/io/measured_sources.hpp"
#include "icobrdf/pipeline/exchanged_pairs.hpp"
#include "icobrdf/pipeline/held_out.hpp"

namespace icobrdf {

namespace {

// The samples' own non-reciprocal fraction and the fit's relative residual (weighted RMS over the weighted RMS of
// the values, worst channel).
struct DataAsymmetry {
  ExchangedAsymmetry pairs;
  bool about_normal = false;  // no exact exchanges: partners up to a rotation about the normal (isotropy assumed)
  double relative_residual = std::nan("");
};

DataAsymmetry data_asymmetry(const FitReport& report) {
  DataAsymmetry d;
  const BrdfSamples& s = *report.samples;
  d.pairs = exchanged_asymmetry(s.wi, s.wr, s.values, false, kSwapToleranceDeg);
  if (d.pairs.samples == 0) {
    d.pairs = exchanged_asymmetry(s.wi, s.wr, s.values, false, kSwapToleranceDeg, true);
    d.about_normal = d.pairs.samples > 0;
  }
  if (!report.checked) return d;
  const Eigen::VectorXd& res = report.checked->fit.residual_rms;
  const double wsum = s.weights.sum();
  for (Eigen::Index c = 0; c < res.size() && c < s.values.cols(); ++c) {
    const double rms = std::sqrt(s.weights.dot(s.values.col(c).cwiseAbs2()) / wsum);
    if (rms > 0) d.relative_residual = std::isnan(d.relative_residual) ? res(c) / rms : std::max(d.relative_residual, res(c) / rms);
  }
  return d;
}

// The largest relative norm of a channel's antisymmetric part: 0 for reciprocal fits (symmetrized exactly),
// the kept antisymmetric terms of a fit with --non-reciprocal (FitRequest::reciprocal).
double kept_antisymmetric_fraction(const Spectrum& s) {
  double x = 0.0;
  if (s.cosine) return x;  // g = f cos(theta_i) is not reciprocal in the first place
  for (const auto& c : s.channels) x = std::max(x, antisymmetric_fraction(c));
  return x;
}

}  // namespace

nlohmann::json fit_report_json(const FitReport& report) {
  const Spectrum& s = report.fit->spectrum;
  const ProjectionContext& ctx = *report.fit->context;
  nlohmann::json j{{"source", s.source},
                   {"output", report.output},
                   {"order", s.order},
                   {"modes", s.modes()},
                   {"level", s.level},
                   {"grid", s.grid_kind},
                   {"cells", ctx.grid->cells()},
                   {"channels", s.channel_count()},
                   {"isotropic", s.isotropic},
                   {"cosine", s.cosine},
                   {"filter", s.filter},
                   {"gram_error", s.gram_error},
                   {"gram_condition", ctx.basis.condition},
                   {"reciprocity_violation", s.reciprocity_violation},
                   {"anisotropy_fraction", s.anisotropy_fraction},
                   {"max_albedo", s.max_albedo},
                   {"antisymmetric_fraction", kept_antisymmetric_fraction(s)},
                   {"seconds", report.seconds}};
  if (!report.grid_fit()) {
    j.erase("gram_error");
    j.erase("gram_condition");
    j["level"] = report.level_asked;
    j["grid_use"] = "albedo figure only";
  }
  if (const CheckedSampleFit* cf = report.checked) {
    const SampleFitResult* sf = &cf->fit;
    const auto vec = [](const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
    j["sample_fit"] = {{"samples", sf->samples},
                       {"unknowns", sf->unknowns},
                       {"effective_rank", sf->effective_rank},
                       {"null_space_dimension", sf->null_space_dimension},
                       {"unseen_modes", sf->unseen_modes},
                       {"rank_threshold", sf->rank_threshold},
                       {"condition_of_kept_part", sf->condition},
                       {"solver", sf->solver},
                       {"dense_kernels", report.dense_kernels},
                       {"tikhonov", sf->tikhonov},
                       {"tikhonov_choice", cf->tikhonov_choice},
                       {"order_choice", cf->order_choice},
                       {"cv_rms", cf->cv_rms},
                       {"cv_folds", cf->cv_folds},
                       {"fallback", cf->fallback},
                       {"effective_dof", sf->hat_trace},
                       {"class_choice", cf->class_choice},
                       {"cv_rms_isotropic", cf->cv_rms_isotropic},
                       {"cv_rms_general", cf->cv_rms_general},
                       {"regularized_for_bound", cf->regularized_for_bound},
                       {"notes", cf->notes},
                       {"noise_sigma", vec(sf->noise_sigma)},
                       {"residual_rms", vec(sf->residual_rms)}};
  }
  if (const KernelFit* k = report.kernels) {
    nlohmann::json weights = nlohmann::json::array(), quantities = nlohmann::json::array();
    for (Eigen::Index c = 0; c < k->weights.cols(); ++c)
      weights.push_back({{"iso", k->weights(0, c)}, {"vol", k->weights(1, c)}, {"geo", k->weights(2, c)}, {"model", "model:" + k->spec(static_cast<int>(c))}});
    const auto vec = [](const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); };
    for (const KernelQuantity& q : k->quantities)
      quantities.push_back({{"name", q.name}, {"value", vec(q.value)}, {"sigma", vec(q.sigma)}, {"inflation", q.inflation}});
    j["kernel_fit"] = {{"kernels", std::string(k->kernels.volume == VolumeKernel::RossThick ? "ross-thick" : "ross-thin") +
                                       (k->kernels.geometric == GeometricKernel::LiSparseR ? " + li-sparse-r" : " + li-dense-r")},
                       {"samples", k->samples},
                       {"weights", weights},
                       {"condition", k->condition},
                       {"determined", k->determined},
                       {"noise_sigma_brf", vec(k->noise_sigma)},
                       {"residual_rms", vec(k->residual_rms)},
                       {"cv_rms", k->cv_rms},
                       {"cv_folds", k->cv_folds},
                       {"solar_zenith_deg", k->solar_zenith * 180.0 / M_PI},
                       {"quantities", quantities},
                       {"supported", supported_fit(k->cv_rms, report.checked ? report.checked->cv_rms : std::nan(""))}};
  }
  if (report.missing_samples >= 0) j["missing_samples"] = report.missing_samples;
  if (report.samples) {
    const DataAsymmetry d = data_asymmetry(report);
    const auto num = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
    j["data_asymmetry"] = {{"exchanged_samples", d.pairs.samples}, {"tolerance_deg", kSwapToleranceDeg}, {"asymmetry", num(d.pairs.asymmetry)},
                           {"median_relative_difference", num(d.pairs.median_relative_difference)},
                           {"relative_residual", num(d.relative_residual)}, {"about_normal", d.about_normal}};
  }
  return j;
}

namespace {

// The lines on the spectrum and the grid: order, modes, channels, and the grid's figures or why there are none.
std::string spectrum_lines(const FitReport& report) {
  const Spectrum& s = report.fit->spectrum;
  const ProjectionContext& ctx = *report.fit->context;
  if (report.grid_fit())
    return fmt::format("  order {} ({} K functions), {} grid level {} ({} cells), {} channel(s){}{}\n", s.order, s.modes(), s.grid_kind,
                       s.level, ctx.grid->cells(), s.channel_count(), s.isotropic ? ", isotropic" : "", s.cosine ? ", g = f cos(theta_i)" : "") +
           fmt::format("  Gram error {:.3g} (condition {:.4g}), reciprocity violation {:.3g}, anisotropic energy {:.3g}\n", s.gram_error,
                       ctx.basis.condition, s.reciprocity_violation, s.anisotropy_fraction);
  return fmt::format("  order {} ({} K functions), {} channel(s){}; {} (no tessellation: the {} grid of level {}, "
                     "{} cells, serves only the albedo figure)\n",
                     s.order, s.modes(), s.channel_count(), s.isotropic ? ", isotropic" : "",
                     report.checked ? "least-squares fit of samples" : "coefficients re-expanded exactly",
                     report.grid_kind == GridKind::EqualArea ? "equal-area" : "geodesic", report.level_asked, ctx.grid->cells()) +
         fmt::format("  reciprocity violation {:.3g}, anisotropic energy {:.3g}\n", s.reciprocity_violation, s.anisotropy_fraction);
}

// The lines on a least-squares fit of samples.
std::string sample_fit_lines(const FitReport& report) {
  const CheckedSampleFit& cf = *report.checked;
  const SampleFitResult& sf = cf.fit;
  double worst = 0.0;
  for (Eigen::Index c = 0; c < sf.residual_rms.size(); ++c) worst = std::max(worst, sf.residual_rms(c));
  std::string out = fmt::format("  sample fit: {} samples, rank {} of {} unknowns (null space {}, unseen modes {}), "
                                "condition {:.3g}, residual RMS {:.3g} 1/sr (worst channel), {}\n",
                                sf.samples, sf.effective_rank, sf.unknowns, sf.null_space_dimension, sf.unseen_modes, sf.condition, worst,
                                sf.solver);
  if (report.dense_kernels != "none") out += "  dense kernels: " + report.dense_kernels + "\n";
  out += fmt::format("  {} order {} ({}), Tikhonov lambda {:.3g} ({}), effective degrees of freedom {:.4g}, {}-fold CV RMS {:.3g} 1/sr\n",
                     report.fit->spectrum.isotropic ? "isotropic modes" : "general modes", report.fit->spectrum.order, cf.order_choice,
                     sf.tikhonov, cf.tikhonov_choice, sf.hat_trace, cf.cv_folds, cf.cv_rms);
  if (cf.class_choice == "cross-validation")
    out += fmt::format("  modes chosen by cross-validation: isotropic CV RMS {:.3g} 1/sr, general CV RMS {:.3g} 1/sr\n", cf.cv_rms_isotropic,
                       cf.cv_rms_general);
  for (const auto& n : cf.notes) out += "  " + n + "\n";
  if (sf.null_space_dimension > 0 && sf.tikhonov == 0.0)
    out += fmt::format("  warning: the samples do not determine every mode; the minimum-norm solution sets the {} undetermined "
                       "combination(s) to zero\n",
                       sf.null_space_dimension);
  return out;
}

// The lines on the kernel-driven fit of the same samples, and which fit the held-out samples support.
std::string kernel_fit_lines(const FitReport& report) {
  const KernelFit& k = *report.kernels;
  std::string out = fmt::format("  kernel-driven fit (Ross-{} + Li-{}, BRF = iso + vol K_vol + geo K_geo): condition {:.3g}{}, "
                                "residual RMS {:.3g} 1/sr, {}-fold CV RMS {:.3g} 1/sr\n",
                                k.kernels.volume == VolumeKernel::RossThick ? "Thick" : "Thin",
                                k.kernels.geometric == GeometricKernel::LiSparseR ? "Sparse-R" : "Dense-R", k.condition,
                                k.determined ? "" : " (the samples do not determine the three weights)", k.residual_rms.maxCoeff(),
                                k.cv_folds, k.cv_rms);
  for (Eigen::Index c = 0; c < k.weights.cols(); ++c)
    out += fmt::format("    channel {}: model:{}\n", c, k.spec(static_cast<int>(c)));
  for (const KernelQuantity& q : k.quantities) {
    std::string values;
    for (Eigen::Index c = 0; c < q.value.size(); ++c)
      values += fmt::format("{}{:.6g} +- {:.2g}", c ? ", " : "", q.value(c), q.sigma(c));
    out += fmt::format("    {}{}: {} (noise inflation 1/WoD {:.3g})\n", q.name,
                       q.name == "white-sky albedo" ? "" : fmt::format(" at sza {:.1f} deg", k.solar_zenith * 180.0 / M_PI), values, q.inflation);
  }
  const double modes = report.checked ? report.checked->cv_rms : std::nan("");
  const std::string which = supported_fit(k.cv_rms, modes);
  out += fmt::format("  the held-out samples support {}: CV RMS kernels {:.3g}, modes {:.3g} 1/sr\n",
                     which == "kernels" ? "the kernel-driven fit (its CV mean square within 0.5% of the modes', or below)"
                     : which == "modes" ? "the modes (their CV error below the kernels')"
                                        : "neither (a CV error is undefined)",
                     k.cv_rms, modes);
  return out;
}

}  // namespace

std::string fit_report_text(const FitReport& report) {
  const Spectrum& s = report.fit->spectrum;
  std::string out = fmt::format("{} -> {}\n", s.source, report.output) + spectrum_lines(report);
  out += fmt::format("  max directional albedo {:.6g}, filter {}, {:.3f} s{}\n", s.max_albedo, s.filter, report.seconds,
                     report.ranks > 1 ? fmt::format(" on {} ranks", report.ranks) : "");
  if (const double anti = kept_antisymmetric_fraction(s); anti > 0)
    out += fmt::format("  antisymmetric terms kept (non-reciprocal fit): {:.3g} of the coefficients' norm\n", anti);
  if (report.checked) out += sample_fit_lines(report);
  if (report.kernels) out += kernel_fit_lines(report);
  if (report.missing_samples >= 0) out += fmt::format("  MERL missing samples (masked, all channels): {}\n", report.missing_samples);
  if (report.samples) {
    const DataAsymmetry d = data_asymmetry(report);
    if (d.pairs.samples == 0)
      out += fmt::format("  the data's non-reciprocal fraction: not measurable (no two samples are each other's exchange within {:.3g} deg)\n",
                         kSwapToleranceDeg);
    else
      out += fmt::format("  the data's non-reciprocal fraction {:.3g} (relative L2 of f - (f + f^T)/2 over the {} samples in exchanged pairs within "
                         "{:.3g} deg{}; median pair difference {:.3g}%), beside the fit's relative residual {:.3g}: a residual at or below it is "
                         "the data's own noise\n",
                         d.pairs.asymmetry, d.pairs.samples, kSwapToleranceDeg,
                         d.about_normal ? ", up to a rotation about the normal (isotropy assumed)" : "", 100 * d.pairs.median_relative_difference,
                         d.relative_residual);
  }
  return out;
}

FitReport fit_report_of(const FitResult& fit, const BrdfSource& source) {
  FitReport report;
  report.fit = &fit;
  report.checked = last_checked_sample_fit(source);
  report.kernels = last_kernel_fit(source);
  report.missing_samples = merl_missing_samples(source);
  return report;
}

void add_rank_split_json(nlohmann::json& j, int ranks, int exchanges, int sample_sums, const std::vector<double>& peak_rss_per_rank) {
  j["ranks"] = ranks;
  j["split"] = exchanges > 0 ? "operators by rows" : sample_sums > 0 ? "samples" : "none";
  j["peak_rss_bytes_per_rank"] = peak_rss_per_rank;  // the operators are split by rows: O(cells x modes / ranks) each
}

}  // namespace icobrdf
