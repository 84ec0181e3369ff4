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
#include "icobrdf/core/basis/helmholtz_modes.hpp"
#include "icobrdf/core/basis/isotropic_modes.hpp"
#include "icobrdf/core/spectrum/spectrum_ops.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/half_angle_file.hpp"
#include "icobrdf/io/spectrum_file.hpp"

namespace icobrdf::cli {
namespace {

// Below this magnitude a coefficient is printed as part of the "zero" count in text mode: far under the
// accuracy of any grid projection (Gram errors are >= 1e-14) and of float32 storage.
constexpr double kPrintZero = 1e-14;

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
  nlohmann::json indices = nlohmann::json::array(), coefficients = nlohmann::json::array();
  double asym = 0.0;
  for (const auto& c : s.channels) asym = std::max(asym, coefficient_asymmetry(c));
  if (s.isotropic) {
    for (const auto& m : isotropic_modes(s.order)) indices.push_back({m.n, m.m, m.l});
    for (const auto& c : s.channels) {
      const Eigen::VectorXd v = ibsss_from_coefficients(c);
      coefficients.push_back(std::vector<double>(v.data(), v.data() + v.size()));
    }
  } else {
    for (const auto& m : helmholtz_modes(s.order)) indices.push_back({m.n, m.l, m.m, m.lp});
    for (const auto& c : s.channels) {
      const Eigen::VectorXd v = bsss_from_coefficients(c);
      coefficients.push_back(std::vector<double>(v.data(), v.data() + v.size()));
    }
  }
  // The standard errors are per fitted unknown; they match the listed modes when the spectrum kept the fit's
  // modes (a filter changes the coefficients, not their count).
  const SampleFitRecord* fit = s.sample_fit ? &*s.sample_fit : nullptr;
  const bool has_se = fit && fit->standard_error.cols() == static_cast<Eigen::Index>(indices.size());
  if (a.json) {
    nlohmann::json j{{"order", s.order},       {"isotropic", s.isotropic}, {"cosine", s.cosine},
                     {"source", s.source},     {"filter", s.filter},       {"indices", indices},
                     {"coefficients", coefficients}, {"asymmetry", asym}, {"representation", representation_name(rec)}};
    if (rec.lobe) j["half_angle"] = lobe;
    if (fit) {
      nlohmann::json se = nlohmann::json::array();
      for (Eigen::Index c = 0; c < fit->standard_error.rows(); ++c) {
        std::vector<double> row(static_cast<size_t>(fit->standard_error.cols()));
        for (Eigen::Index k = 0; k < fit->standard_error.cols(); ++k) row[static_cast<size_t>(k)] = fit->standard_error(c, k);
        se.push_back(row);
      }
      j["sample_fit"] = {{"samples", fit->samples},       {"unknowns", fit->unknowns},
                         {"effective_rank", fit->effective_rank}, {"condition", fit->condition},
                         {"residual_rms", fit->residual_rms}, {"noise_sigma", fit->noise_sigma},
                         {"cv_rms", fit->cv_rms},         {"cv_folds", fit->cv_folds},
                         {"tikhonov", fit->tikhonov},     {"tikhonov_power", fit->tikhonov_power},
                         {"order_choice", fit->order_choice}, {"tikhonov_choice", fit->tikhonov_choice},
                         {"fallback", fit->fallback},     {"solver", fit->solver},
                         {"effective_dof", fit->effective_dof}, {"class_choice", fit->class_choice},
                         {"cv_rms_isotropic", fit->cv_rms_isotropic}, {"cv_rms_general", fit->cv_rms_general},
                         {"standard_errors", se}};
    }
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
  size_t zeros = 0;
  for (size_t k = 0; k < indices.size(); ++k) {
    bool all_zero = true;
    for (const auto& ch : coefficients) all_zero = all_zero && std::abs(ch[k].get<double>()) < kPrintZero;
    if (all_zero && !a.all) {
      ++zeros;
      continue;
    }
    std::string line = "  " + indices[k].dump();
    for (size_t c = 0; c < coefficients.size(); ++c) {
      line += fmt::format("  {: .10e}", coefficients[c][k].get<double>());
      if (has_se) line += fmt::format(" +- {:.3e}", fit->standard_error(static_cast<Eigen::Index>(c), static_cast<Eigen::Index>(k)));
    }
    std::cout << line << "\n";
  }
  if (zeros) std::cout << fmt::format("  ({} coefficients below {:.0e} not listed; --all lists them)\n", zeros, kPrintZero);
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
