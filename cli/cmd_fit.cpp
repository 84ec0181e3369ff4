// icobrdf fit SOURCE --order N --level L [--isotropic] [--cosine] [--filter NAME] -o SPECTRUM.h5
// Projects a BRDF onto the Helmholtz modes on a tessellation and writes its spectrum.
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "cli/option_checks.hpp"
#include "io/brdf_source.hpp"
#include "io/measured_sources.hpp"
#include "io/output_path.hpp"
#include "core/error.hpp"
#include "io/spectrum_file.hpp"
#include "pipeline/fit_source.hpp"
#include "pipeline/reflectance_check.hpp"

namespace icobrdf::cli {
namespace {

struct FitArgs {
  std::string source, output, filter = "none", grid = "equal-area", sampling = "average", name;
  int order = 8, level = 4;
  bool isotropic = false, cosine = false, json = false, strict = false;
  double gram_tol = kDefaultGramTolerance;
};

GridKind fitting_grid_kind(const std::string& text) {
  if (text == to_string(GridKind::EqualArea)) return GridKind::EqualArea;
  if (text == to_string(GridKind::Geodesic)) return GridKind::Geodesic;
  throw ArgumentError("--grid: expected 'equal-area' or 'geodesic', found '" + quoted_text(text) + "'");
}

void run_fit(const FitArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  FitRequest r;
  r.level = a.level;
  r.order = a.order;
  r.isotropic = a.isotropic;
  r.cosine = a.cosine;
  r.filter = parse_lowpass_filter(a.filter);
  r.gram_tolerance = a.gram_tol;
  const auto sampling = lut_sampling_named(a.sampling);
  if (!sampling) throw ArgumentError("--sampling: expected 'average' or 'centre', found '" + a.sampling + "'");
  r.sampling = *sampling;
  check_output_path(a.output, {a.source});
  require_storable_source(a.source);
  const auto source = open_source(a.source);  // validates the source before any work
  if (!source->has_delta())  // a model's delta note is about pointwise values, which fit does not print
    for (const auto& note : source->notes()) std::cerr << "icobrdf: note: " << source->spec() << ": " << note << "\n";
  r.grid_kind = fitting_grid_kind(a.grid);
  const FitResult fit = fit_source(*source, r);
  const Spectrum& s = fit.spectrum;
  const ProjectionContext& ctx = *fit.context;
  check_fitted_albedo(s, *ctx.grid, "fit " + quoted_text(s.source), {a.strict, &std::cerr});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  write_spectrum_file(a.output, s, nullptr, a.name.empty() ? "material" : a.name);
  nlohmann::json j{{"source", s.source},
                   {"output", a.output},
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
                   {"seconds", seconds}};
  // Scattered-sample fits (MERL, CSV): the least-squares figures, so rank-deficient data is visible.
  const SampleFitResult* sf = last_sample_fit(*source);
  const std::int64_t missing = merl_missing_samples(*source);
  if (sf) {
    const auto& sv = sf->singular_values;
    const double cond = sf->effective_rank > 0 ? sv(0) / sv(sf->effective_rank - 1) : 0.0;
    j["sample_fit"] = {{"samples", sf->samples},
                       {"unknowns", sf->unknowns},
                       {"effective_rank", sf->effective_rank},
                       {"null_space_dimension", sf->null_space_dimension},
                       {"unseen_modes", sf->unseen_modes},
                       {"rank_threshold", sf->rank_threshold},
                       {"condition_of_kept_part", cond},
                       {"residual_rms", std::vector<double>(sf->residual_rms.data(), sf->residual_rms.data() + sf->residual_rms.size())}};
  }
  if (missing >= 0) j["missing_samples"] = missing;
  if (a.json) {
    std::cout << j.dump(2) << "\n";
    return;
  }
  std::cout << fmt::format("{} -> {}\n", s.source, a.output)
            << fmt::format("  order {} ({} K functions), {} grid level {} ({} cells), {} channel(s){}{}\n", s.order, s.modes(),
                           s.grid_kind, s.level, ctx.grid->cells(), s.channel_count(), s.isotropic ? ", isotropic" : "",
                           s.cosine ? ", g = f cos(theta_i)" : "")
            << fmt::format("  Gram error {:.3g} (condition {:.4g}), reciprocity violation {:.3g}, anisotropic energy {:.3g}\n",
                           s.gram_error, ctx.basis.condition, s.reciprocity_violation, s.anisotropy_fraction)
            << fmt::format("  max directional albedo {:.6g}, filter {}, {:.3f} s\n", s.max_albedo, s.filter, seconds);
  if (sf) {
    double worst = 0.0;
    for (Eigen::Index c = 0; c < sf->residual_rms.size(); ++c) worst = std::max(worst, sf->residual_rms(c));
    std::cout << fmt::format("  sample fit: {} samples, rank {} of {} unknowns (null space {}, unseen modes {}), "
                             "condition {:.3g}, residual RMS {:.3g} 1/sr (worst channel)\n",
                             sf->samples, sf->effective_rank, sf->unknowns, sf->null_space_dimension, sf->unseen_modes,
                             j["sample_fit"]["condition_of_kept_part"].get<double>(), worst);
    if (sf->null_space_dimension > 0)
      std::cout << "  warning: the samples do not determine every mode; the minimum-norm solution sets the "
                << sf->null_space_dimension << " undetermined combination(s) to zero\n";
  }
  if (missing >= 0) std::cout << fmt::format("  MERL missing samples (masked, all channels): {}\n", missing);
}

void add_fit_command(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  auto* cmd = app.add_subcommand("fit", "Project a BRDF onto the Helmholtz modes and write its spectrum (HDF5)");
  cmd->add_option("source", a->source, "SOURCE: model:NAME[:key=value,...] (see `icobrdf models`) or a spectrum/bank file")->required();
  cmd->add_option("--order,-n", a->order, "Total order N of the expansion")->capture_default_str()->check(CLI::Range(0, 128));
  cmd->add_option("--level,-l", a->level, "Tessellation level (cells: 10*4^L + 2^(L+1))")->capture_default_str()->check(CLI::Range(0, 8));
  cmd->add_flag("--isotropic", a->isotropic, "Project onto the isotropic modes (IBSSS)");
  cmd->add_flag("--cosine", a->cosine, "Project g = f cos(theta_i) (always for delta models)");
  cmd->add_option("--filter", a->filter, "Low-pass filter: none, fejer, lanczos, hann, gaussian[:width=W]")->capture_default_str();
  cmd->add_option("--grid", a->grid, "Tessellation: equal-area or geodesic")->capture_default_str();
  cmd->add_option("--sampling", a->sampling, "LUT sampling: average (cell cubature) or centre")->capture_default_str();
  cmd->add_option("--gram-tol", a->gram_tol, "Largest Gram error max|G - I| accepted")->capture_default_str()->check(gram_tolerance());
  cmd->add_option("--name", a->name, "Material name inside the file (default: material)");
  cmd->add_option("-o,--output", a->output, "Output spectrum file (.h5)")->required();
  cmd->add_flag("--json", a->json, "Print the figures as JSON");
  cmd->add_flag("--strict", a->strict, "A negative directional albedo (non-physical) is an error, not a warning");
  cmd->callback([a] { run_fit(*a); });
}

const CommandRegistrar kRegistrar("fit", add_fit_command);

}  // namespace
}  // namespace icobrdf::cli
