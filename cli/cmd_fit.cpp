// icobrdf fit SOURCE [--order N] --level L [--isotropic] [--cosine] [--filter NAME] [--quiet] -o SPECTRUM.h5
// Projects a BRDF onto the Helmholtz modes on a tessellation and writes its spectrum. Scattered samples
// (CSV) without --order get a cross-validated order; a fit longer than kProgressDelaySeconds reports its
// stages on stderr. Under `mpirun -np R` the streaming projection of a model (or an RGL material, or a
// half-angle lobe) is spread over the R ranks (icobrdf/cluster/distributed_run.hpp), and so are the passes of a
// least-squares fit over its samples (MERL tables, CSV samples); rank 0 writes and prints.
#include <nlohmann/json.hpp>

#include <chrono>
#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "cli/error_report.hpp"
#include "cli/option_checks.hpp"
#include "icobrdf/blas/blas_dense_kernels.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/measured_sources.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/progress.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/lab/process_usage.hpp"
#include "icobrdf/pipeline/fit_report.hpp"
#include "icobrdf/pipeline/fit_order.hpp"
#include "icobrdf/pipeline/fit_source.hpp"
#include "icobrdf/pipeline/reflectance_check.hpp"

namespace icobrdf::cli {
namespace {

struct FitArgs {
  std::string source, output, filter = "none", grid = "equal-area", sampling = "average", name;
  int order = kDefaultFitOrder, level = 4;
  bool order_given = false;
  bool isotropic = false, cosine = false, json = false, strict = false, quiet = false, non_reciprocal = false;
  double gram_tol = kDefaultGramTolerance;
};

GridKind fitting_grid_kind(const std::string& text) {
  if (text == to_string(GridKind::EqualArea)) return GridKind::EqualArea;
  if (text == to_string(GridKind::Geodesic)) return GridKind::Geodesic;
  throw ArgumentError("--grid: expected 'equal-area' or 'geodesic', found '" + quoted_text(text) + "'");
}

void run_fit(const FitArgs& a, const DistributedRun& run) {
  const auto t0 = std::chrono::steady_clock::now();
  FitRequest r;
  r.share = run.share;
  r.level = a.level;
  r.order = a.order;
  if (a.quiet) set_progress_stream(nullptr);  // the projection's lines too
  if (run.writes()) r.progress = stage_progress_lines("fit");
  r.isotropic = a.isotropic;
  r.reciprocal = !a.non_reciprocal;
  r.cosine = a.cosine;
  r.filter = parse_lowpass_filter(a.filter);
  r.gram_tolerance = a.gram_tol;
  const auto sampling = lut_sampling_named(a.sampling);
  if (!sampling) throw ArgumentError("--sampling: expected 'average' or 'centre', found '" + a.sampling + "'");
  r.sampling = *sampling;
  if (run.writes()) check_output_path(a.output, {a.source});
  require_storable_source(a.source);
  const auto source = open_source(a.source);  // validates the source before any work
  if (!source->has_delta() && run.writes())  // a model's delta note is about pointwise values, which fit does not print
    for (const auto& note : source->notes()) std::cerr << "icobrdf: note: " << source->spec() << ": " << note << "\n";
  r.order = fit_order_for(*source, a.order_given ? std::optional<int>(a.order) : std::nullopt);
  if (a.non_reciprocal && source->values_only_at_samples())
    throw ArgumentError("--non-reciprocal: '" + quoted_text(a.source) + "' holds scattered samples, which are fitted on the reciprocal modes only");
  r.grid_kind = fitting_grid_kind(a.grid);
  run.setup_done();
  const FitResult fit = fit_source(*source, r);
  const std::vector<double> rss = run.ranks > 1 ? run.gather(lab::peak_resident_bytes()) : std::vector<double>{};  // collective
  if (!run.writes()) return;  // rank 0 checks, writes and reports
  const Spectrum& s = fit.spectrum;
  if (run.ranks > 1 && run.exchanges() == 0 && run.sample_sums() == 0)
    std::cerr << "icobrdf: note: " << s.source << " is not fitted by streaming projection; each of the " << run.ranks
              << " ranks fitted it whole\n";
  check_fitted_albedo(s, *fit.context->grid, "fit " + quoted_text(s.source), {a.strict, &std::cerr});
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  write_spectrum_file(a.output, s, nullptr, a.name.empty() ? "material" : a.name);
  FitReport report = fit_report_of(fit, *source);
  report.samples = samples_of(*source);
  report.output = a.output;
  report.level_asked = a.level;
  report.grid_kind = r.grid_kind;
  report.seconds = seconds;
  report.ranks = run.ranks;
  // The dense kernels solved the normal equations, if those ran (the QR path uses none).
  if (report.checked && std::string(report.checked->fit.solver) == "normal equations") report.dense_kernels = fit_kernel_choice().reason;
  if (report.checked && !report.checked->fallback.empty())
    std::cerr << ("icobrdf: warning: fit " + quoted_text(s.source) + ": " + report.checked->fallback + "\n");
  if (!a.json) {
    std::cout << fit_report_text(report);
    return;
  }
  nlohmann::json j = fit_report_json(report);
  if (run.ranks > 1) add_rank_split_json(j, run.ranks, run.exchanges(), run.sample_sums(), rss);
  std::cout << j.dump(2) << "\n";
}

void add_fit_command(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  auto* cmd = app.add_subcommand("fit", "Project a BRDF onto the Helmholtz modes and write its spectrum (HDF5)");
  cmd->footer(
      "Samples (FILE.csv or samples:FILE, columns theta_i,phi_i,theta_r,phi_r,value[s], degrees) take options after '#',\n"
      "comma-separated, e.g. 'data.csv#tikhonov=auto,power=1':\n"
      "  radians          angles in radians\n"
      "  strict           non-reciprocal sample pairs are an error\n"
      "  tikhonov=L|auto  penalty L * sum_k d_k x_k^2, d_k = (n(n+2) + m(m+2))^p; auto: L by generalized cross-validation\n"
      "  power=P          the exponent p of the penalty (default 1; 0 = plain ridge)\n"
      "  rank-tol=T       relative singular-value threshold of the rank (default max(samples, unknowns) * 2.2e-16)\n"
      "Without --order, the modes (isotropic or general; only isotropic with --isotropic) and their order are chosen\n"
      "by 5-fold cross-validation on the same folds, and lambda by generalized cross-validation (unless tikhonov=L is\n"
      "given); the choices and both classes' CV errors are printed. Samples that do not determine the modes (in-plane\n"
      "data against anisotropic modes, unseen modes, condition > 1e6) fall back to the isotropic modes, then to a\n"
      "regularized fit, and say so; a fit reaching over 10 times the largest sample anywhere is regularized instead\n"
      "(the GCV-best lambda whose fit stays within that bound).\n"
      "CURET: curet:abrdf.dat#sample=N[,table=FILE] (table.txt beside abrdf.dat by default). Sample angles: degrees\n"
      "unless declared radians (#radians, '# units: radians', or columns theta_i_rad,...); theta < 0 = the direction\n"
      "at phi + 180 deg (NIST's signed in-plane angles).\n"
      "The spectrum file keeps the fit's record: standard errors, CV error, rank, condition, residual RMS.");
  cmd->add_option("source", a->source, "SOURCE: model:NAME[:key=value,...] (see `icobrdf models`), a spectrum/bank file, "
                                       "FILE.csv[#OPTIONS] samples, FILE.binary MERL, FILE.zernike.csv SCATMECH")->required();
  cmd->add_option("--order,-n", a->order, "Total order N of the expansion (default 8; samples: chosen by cross-validation)")
      ->check(CLI::Range(0, 128))
      ->each([a](const std::string&) { a->order_given = true; });
  cmd->add_option("--level,-l", a->level, "Tessellation level (cells: 10*4^L + 2^(L+1))")->capture_default_str()->check(CLI::Range(0, 8));
  cmd->add_flag("--isotropic", a->isotropic, "Project onto the isotropic modes (IBSSS)");
  cmd->add_flag("--cosine", a->cosine, "Project g = f cos(theta_i) (always for delta models)");
  cmd->add_flag("--non-reciprocal", a->non_reciprocal, "Keep the antisymmetric terms of a non-reciprocal source (K&vD sec. 2B)");
  cmd->add_option("--filter", a->filter, "Low-pass filter: none, fejer, lanczos, hann, gaussian[:width=W]")->capture_default_str();
  cmd->add_option("--grid", a->grid, "Tessellation: equal-area or geodesic")->capture_default_str();
  cmd->add_option("--sampling", a->sampling, "LUT sampling: average (cell cubature) or centre")->capture_default_str();
  cmd->add_option("--gram-tol", a->gram_tol, "Largest Gram error max|G - I| accepted")->capture_default_str()->check(gram_tolerance());
  cmd->add_option("--name", a->name, "Material name inside the file (default: material)");
  cmd->add_option("-o,--output", a->output, "Output spectrum file (.h5)")->required();
  cmd->add_flag("--json", a->json, "Print the figures as JSON");
  cmd->add_flag("--strict", a->strict, "A negative directional albedo (non-physical) is an error, not a warning");
  cmd->add_flag("--quiet,-q", a->quiet, "No progress lines on stderr (printed for fits longer than 2 s)");
  cmd->callback([a] { run_distributed("fit", 1, [a](const DistributedRun& run) { run_fit(*a, run); }, true, rank_errors()); });
}

const CommandRegistrar kCmdFitRegistrar("fit", add_fit_command);

}  // namespace
}  // namespace icobrdf::cli
