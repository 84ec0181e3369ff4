// icobrdf plot basis|slice|spectrum|sphere|curves|albedo|halfdiff|samples|bytes ... -o FILE.png: the pictures of icobrdf/plot/
// (docs/plots.md), written atomically. SOURCEs are loaded by icobrdf/pipeline/picture_source.hpp and the option forms read by
// icobrdf/plot/plot_options.hpp; this file only wires flags to them.
#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "cli/option_checks.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/plot/bytes_plot.hpp"
#include "icobrdf/plot/curve_plots.hpp"
#include "icobrdf/plot/half_diff_plot.hpp"
#include "icobrdf/plot/picture_materials.hpp"
#include "icobrdf/plot/plot_options.hpp"
#include "icobrdf/plot/plots.hpp"

namespace icobrdf::cli {
namespace {

constexpr double kRadPerDeg = M_PI / 180.0;
constexpr int kMaxPlotOrder = 32;           // largest truncation order a slice or sphere fit is drawn at
constexpr int kMinSphereSize = 16, kMaxSphereSize = 2048;

struct PlotArgs {
  std::string source, output, filter = "none", light = "45,135", shading = "auto";
  int order = 4, level = 4, size = 256, panel = 200, basis_panel = 0;
  std::vector<int> orders{0, 1, 2, 4, 6, 8};
  std::vector<double> thetas{0.0, 30.0, 60.0};
  double theta_i = 45.0, phi_i = 0.0, sky_radiance = 0.3, exposure = 1.0, phi_d = 90.0;
  bool separate = false, sky = false, no_exact = false, json = false, strict = false, log = false;
};

void report(const PlotArgs& a, nlohmann::json j) {
  if (a.json) std::cout << j.dump(2) << "\n";
  else std::cout << "wrote " << j["output"].get<std::string>() << "\n";
}

void add_basis_command(CLI::App* plot, const std::shared_ptr<PlotArgs>& a) {
  auto* basis = plot->add_subcommand("basis", "Every K_n^l up to --order on the Lambert disk (density + contours)");
  basis->add_option("--order,-n", a->order, "Largest order n")->capture_default_str()->check(CLI::Range(0, plot::kMaxBasisOrder));
  basis->add_option("--panel", a->basis_panel, "Disk diameter in pixels (default: from the order)")
      ->check(CLI::Range(plot::kMinBasisPanel, plot::kMaxBasisPanel));
  basis->add_flag("--separate", a->separate, "Also write one PNG per function, K_<n>_<l>.png");
  basis->add_option("-o,--output", a->output, "Output FILE.png, or an existing folder (writes FOLDER/basis.png)")->required();
  basis->add_flag("--json", a->json, "Print the files written as JSON");
  basis->callback([a] {
    const auto files = plot::plot_basis(a->order, a->output, a->separate, a->basis_panel);
    if (a->json) std::cout << nlohmann::json{{"files", files}}.dump(2) << "\n";
    else for (const auto& f : files) std::cout << "wrote " << f << "\n";
  });
}

void add_slice_command(CLI::App* plot, const std::shared_ptr<PlotArgs>& a) {
  auto* slice = plot->add_subcommand("slice", "Remitted distribution for one incident direction, several truncation orders");
  slice->add_option("source", a->source, "SOURCE: model:NAME[:key=value,...] or FILE.h5[#material]")->required();
  slice->add_option("--theta-i", a->theta_i, "Polar angle of incidence [deg], 0 <= theta_i < 90")->capture_default_str()->check(finite_in(0, 90, false, true));
  slice->add_option("--phi-i", a->phi_i, "Azimuth of incidence [deg]")->capture_default_str()->check(finite_in(-360, 360));
  slice->add_option("--order,-n", a->orders, "Truncation orders side by side (at most 9): 2,4,7 or 2 4 7; measured data are fitted only when given")
      ->capture_default_str()->expected(1, 9)->delimiter(',')->check(CLI::Range(0, kMaxPlotOrder));
  slice->add_flag("--log", a->log, "Logarithmic colour and polar scale");
  slice->add_option("--filter", a->filter, "Low-pass filter per order: none, fejer, lanczos, hann, gaussian[:width=W]")->capture_default_str();
  slice->add_option("--level,-l", a->level, "Grid level of the fit of a model")->capture_default_str()->check(CLI::Range(0, 8));
  slice->add_option("--panel", a->panel, "Disk diameter in pixels")->capture_default_str()->check(CLI::Range(64, 800));
  slice->add_flag("--no-exact", a->no_exact, "Do not add the model itself as a last column");
  slice->add_option("-o,--output", a->output, "Output PNG")->required();
  slice->callback([a, slice] {
    plot::SliceRequest q = plot::slice_request(a->theta_i, a->phi_i, a->filter, a->panel, !a->no_exact, a->log);
    check_output_path(a->output, {a->source});
    const plot::SliceSource src = plot::load_slice_source(a->source, a->orders, slice->count("--order") > 0, a->level);
    q.orders = a->orders;
    const auto f = plot::plot_slice(src, q, a->output);
    report(*a, {{"output", a->output}, {"width", f.width}, {"height", f.height}, {"scale", f.scale}, {"signed", f.signed_map},
                {"quantity", f.g_form ? "g" : "f"}, {"columns", f.disks.size()}});
  });
}

void add_plot_spectrum_command(CLI::App* plot, const std::shared_ptr<PlotArgs>& a) {
  auto* spec = plot->add_subcommand("spectrum", "IBSSS overview (paper Fig. 3) and the coefficient matrix of a spectrum file");
  spec->add_option("source", a->source, "SPECTRUM.h5[#material]")->required();
  spec->add_option("-o,--output", a->output, "Output PNG")->required();
  spec->add_flag("--log", a->log, "Signed logarithmic colour scale");
  spec->callback([a] {
    const Spectrum s = plot::load_spectrum_picture(a->source);
    check_output_path(a->output, {a->source});
    const auto f = plot::plot_spectrum(s, a->source, a->output, a->log);
    report(*a, {{"output", a->output}, {"width", f.width}, {"height", f.height}, {"order", s.order}, {"matrix", f.matrix_drawn}});
  });
}

void add_sphere_command(CLI::App* plot, const std::shared_ptr<PlotArgs>& a) {
  auto* sphere = plot->add_subcommand("sphere", "A sphere of the material lit by a distant light (a grid for a bank)");
  sphere->add_option("source", a->source, "SOURCE: model:..., FILE.h5[#material], or BANK.h5 (all materials)")->required();
  sphere->add_option("--light", a->light, "Light direction THETA,PHI [deg] in the camera frame (theta from the viewing axis)")
      ->capture_default_str();
  sphere->add_flag("--sky", a->sky, "Add a uniform sky (radiance --sky-radiance)");
  sphere->add_option("--sky-radiance", a->sky_radiance, "Sky radiance with --sky")->capture_default_str()->check(finite_in(0, kAnyFinite));
  sphere->add_option("--exposure", a->exposure, "Radiance shown as white")->capture_default_str()->check(finite_in(0, kAnyFinite, true));
  sphere->add_option("--size", a->size, "Sphere diameter in pixels")->capture_default_str()->check(CLI::Range(kMinSphereSize, kMaxSphereSize));
  sphere->add_option("--order,-n", a->orders, "Order of the fit when shading from a spectrum (one value)")->expected(1)->delimiter(',')->check(CLI::Range(0, kMaxPlotOrder));
  sphere->add_option("--level,-l", a->level, "Grid level of that fit")->capture_default_str()->check(CLI::Range(0, 8));
  sphere->add_option("--shading", a->shading, "auto (the values when known everywhere), model (those values), or spectrum")->capture_default_str();
  sphere->add_option("-o,--output", a->output, "Output PNG")->required();
  sphere->add_flag("--strict", a->strict, "Negative reflectance of a material is an error (default: a warning)");
  sphere->callback([a, sphere] {
    const plot::SphereRequest q = plot::sphere_request(a->light, a->sky ? a->sky_radiance : 0.0, a->exposure, a->size, a->shading);
    constexpr int kDefaultSphereOrder = 8;
    const int order = sphere->count("--order") ? a->orders.front() : kDefaultSphereOrder;
    check_output_path(a->output, {a->source});
    const auto materials = plot::load_sphere_materials(a->source, q.shading, order, a->level, "--shading model");
    plot::check_sphere_albedo(materials, a->strict);
    const auto f = plot::plot_sphere(a->source, materials, q, a->output);
    report(*a, {{"output", a->output}, {"width", f.width}, {"height", f.height}, {"spheres", f.names}});
  });
}

// plot curves / albedo / halfdiff / samples / bytes: the SOURCE's values (unfitted when known everywhere) along the plane of
// incidence, integrated over the hemisphere against theta_i, as an image over (theta_h, theta_d); scattered samples over
// their fit; a bank material's candidates, error against bytes.
void add_curve_commands(CLI::App* plot, const std::shared_ptr<PlotArgs>& a) {
  auto* curves = plot->add_subcommand("curves", "In-plane curves, Cartesian and polar, for several theta_i");
  auto* albedo = plot->add_subcommand("albedo", "Directional albedo against theta_i, per channel");
  auto* halfdiff = plot->add_subcommand("halfdiff", "f against theta_h and theta_d at one phi_d, as MERL pictures");
  auto* samples = plot->add_subcommand("samples", "Scattered samples (CSV, CURET) over their fitted in-plane curves, residuals below");
  for (auto* c : {curves, albedo, halfdiff, samples}) {
    c->add_option("source", a->source, "SOURCE: model:..., measured file, FILE.h5[#material]")->required();
    if (c != samples) c->add_option("--phi-i", a->phi_i, "Azimuth of incidence [deg]")->capture_default_str()->check(finite_in(-360, 360));
    c->add_option("--order,-n", a->order, "Order of a fit, for sources without values everywhere (samples: chosen by cross-validation)")->check(CLI::Range(0, kMaxPlotOrder));
    c->add_option("-o,--output", a->output, "Output PNG")->required();
  }
  for (auto* c : {curves, samples})
    c->add_option("--theta-i", a->thetas, "Polar angles of incidence [deg]: 0,30,60 or 0 30 60 (samples: the most measured)")->delimiter(',')
        ->expected(1, static_cast<int>(plot::kMaxCurves))->check(finite_in(0, 90, false, true));
  for (auto* c : {curves, halfdiff, samples}) c->add_flag("--log", a->log, "Logarithmic value scale");
  halfdiff->add_option("--phi-d", a->phi_d, "Difference azimuth phi_d [deg]")->capture_default_str()->check(finite_in(-360, 360));
  const auto values = [a] {
    check_output_path(a->output, {a->source});
    return plot::load_picture_values(a->source, a->order, a->level);
  };
  curves->callback([a, values] {
    const plot::PictureValues v = values();
    plot::CurveRequest q{{}, a->phi_i * kRadPerDeg, a->log};
    for (double t : a->thetas) q.theta_i.push_back(t * kRadPerDeg);
    plot::plot_curves(a->source, v.values, v.quantity, q, a->output);
    report(*a, {{"output", a->output}});
  });
  albedo->callback([a, values] {
    const plot::PictureValues v = values();
    plot::plot_albedo(a->source, v.values, v.channels, {}, a->phi_i * kRadPerDeg, a->output);
    report(*a, {{"output", a->output}});
  });
  halfdiff->callback([a, values] {
    plot::plot_half_diff(a->source, values().values, a->log, a->output, plot::kHalfDiffSize, a->phi_d * kRadPerDeg);
    report(*a, {{"output", a->output}});
  });
  samples->callback([a, samples] {
    check_output_path(a->output, {a->source});
    const plot::SamplePicture p = plot::load_sample_picture(a->source, samples->count("--order") ? a->order : -1, a->level);
    plot::SamplePlotRequest q{{}, a->log};
    if (samples->count("--theta-i")) for (double t : a->thetas) q.theta_i.push_back(t * kRadPerDeg);
    const auto f = plot::plot_samples(a->source, p.samples, p.fit, p.fit_label, q, a->output);
    report(*a, {{"output", a->output}, {"width", f.width}, {"height", f.height}, {"samples", f.total}, {"drawn", f.points.size()},
                {"theta_i", f.group_theta_deg}, {"residual_rms", f.residual_rms}, {"fit", p.fit_label}});
  });
  auto* bytes = plot->add_subcommand("bytes", "Error against bytes of the candidates of a bank material, log-log");
  bytes->add_option("source", a->source, "BANK.h5[#material] (a bank built by bank build)")->required();
  bytes->add_option("-o,--output", a->output, "Output PNG")->required();
  bytes->callback([a] {
    check_output_path(a->output, {a->source});
    const auto f = plot::plot_bytes(a->source, read_bank_candidates(a->source), a->output);
    report(*a, {{"output", a->output}, {"width", f.width}, {"height", f.height}, {"points", f.points}, {"representations", f.representations}});
  });
}

void add_plot_command(CLI::App& app) {
  auto a = std::make_shared<PlotArgs>();
  auto* plot = app.add_subcommand("plot", "Draw PNG pictures: basis functions, slices, spectra, lit spheres, curves, albedo");
  plot->require_subcommand(1);
  add_basis_command(plot, a);
  add_slice_command(plot, a);
  add_plot_spectrum_command(plot, a);
  add_sphere_command(plot, a);
  add_curve_commands(plot, a);
  for (auto* c : plot->get_subcommands([](CLI::App*) { return true; }))
    if (!c->get_option_no_throw("--json")) c->add_flag("--json", a->json, "Print the figures as JSON");
}

const CommandRegistrar kCmdPlotRegistrar("plot", add_plot_command);

}  // namespace
}  // namespace icobrdf::cli
