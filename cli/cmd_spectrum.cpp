// icobrdf spectrum SPECTRUM.h5[#MATERIAL] [--json]: the coefficients with their indices.
// Isotropic spectra print the IBSSS a_nm^l with [n, m, l]; others the Helmholtz BSSS a_ab with
// [n, l, m, l'] (the order of icobrdf/core/basis/helmholtz_modes.hpp), as `icobrdf modes` indexes them.
// A spectrum fitted to samples also prints its fit record (samples, rank, condition, residual RMS, CV error,
// choices) and each coefficient's standard error ("+- se").
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <iostream>

#include "cli/commands.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/half_angle_file.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/io/spectrum_listing.hpp"

namespace icobrdf::cli {
namespace {

struct SpectrumArgs {
  std::string file;
  bool json = false, all = false;
};

void run_spectrum(const SpectrumArgs& a) {
  const MaterialRef ref = split_material_ref(a.file);
  const MaterialRecord rec = read_bank_material(ref.path, ref.name, ReadOptions{h5::kDefaultMaxDatasetBytes, false});
  const Spectrum& s = rec.spectrum;
  // A half-angle lobe (representations "half-angle" and "hybrid") is listed after the modes.
  const nlohmann::json lobe = rec.lobe ? half_angle_summary(*rec.lobe) : nlohmann::json();
  const SpectrumListing listing = list_spectrum(s);
  const double asym = listing.asymmetry;
  // The standard errors are per fitted unknown; they match the listed modes when the spectrum kept the fit's
  // modes (a filter changes the coefficients, not their count).
  const SampleFitRecord* fit = s.sample_fit ? &*s.sample_fit : nullptr;
  const bool has_se = fit && fit->standard_error.cols() == static_cast<Eigen::Index>(listing.indices.size());
  if (a.json) {
    nlohmann::json j{{"order", s.order},       {"isotropic", s.isotropic}, {"cosine", s.cosine},
                     {"source", s.source},     {"filter", s.filter},       {"indices", listing.indices},
                     {"coefficients", listing.coefficients}, {"asymmetry", asym}, {"representation", representation_name(rec)}};
    if (rec.lobe) j["half_angle"] = lobe;
    if (fit) j["sample_fit"] = sample_fit_record_json(*fit);
    std::cout << j.dump() << "\n";
    return;
  }
  std::cout << fmt::format("{}: {} of order {} ({}), source {}, filter {}\n", a.file, s.isotropic ? "IBSSS" : "BSSS", s.order,
                           s.cosine ? "g = f cos(theta_i)" : "f", s.source, s.filter);
  if (s.cosine && asym > 0)
    std::cout << fmt::format("  note: the spectrum of g is not symmetric (asymmetry {:.3g}); listed is its reciprocal part\n", asym);
  if (fit) {
    double rms = 0.0, sigma = 0.0;
    for (double x : fit->residual_rms) rms = std::max(rms, x);
    for (double x : fit->noise_sigma) sigma = std::max(sigma, x);
    std::cout << fmt::format("  sample fit: {} samples, rank {} of {} unknowns, condition {:.3g}, residual RMS {:.3g} 1/sr, "
                             "sigma {:.3g} 1/sr (worst channel), {}-fold CV RMS {:.3g} 1/sr\n",
                             fit->samples, fit->effective_rank, fit->unknowns, fit->condition, rms, sigma, fit->cv_folds, fit->cv_rms)
              << fmt::format("  order {}, Tikhonov lambda {:.3g} (power {:.3g}, {}), {}\n", fit->order_choice, fit->tikhonov,
                             fit->tikhonov_power, fit->tikhonov_choice, fit->solver);
    if (fit->class_choice == "cross-validation")
      std::cout << fmt::format("  modes chosen by cross-validation: isotropic CV RMS {:.3g}, general CV RMS {:.3g} 1/sr; "
                               "effective degrees of freedom {:.4g}\n",
                               fit->cv_rms_isotropic, fit->cv_rms_general, fit->effective_dof);
    if (!fit->fallback.empty()) std::cout << "  fallback: " << fit->fallback << "\n";
  }
  std::cout << spectrum_listing_text(listing, has_se ? &fit->standard_error : nullptr, a.all, "--all lists them");
  if (rec.lobe) std::cout << fmt::format("  {}: + {}\n", representation_name(rec), half_angle_summary_line(*rec.lobe, true));
}

void add_spectrum_command(CLI::App& app) {
  auto a = std::make_shared<SpectrumArgs>();
  auto* cmd = app.add_subcommand("spectrum", "Print a spectrum's coefficients with their mode indices");
  cmd->add_option("file", a->file, "SPECTRUM.h5 or BANK.h5#MATERIAL")->required();
  cmd->add_flag("--json", a->json, "JSON: {order, isotropic, indices, coefficients: [one list per channel]}");
  cmd->add_flag("--all", a->all, "Also list coefficients that are zero");
  cmd->callback([a] { run_spectrum(*a); });
}

const CommandRegistrar kCmdSpectrumRegistrar("spectrum", add_spectrum_command);

}  // namespace
}  // namespace icobrdf::cli
