// icobrdf plot basis|slice|spectrum|sphere ... -o FILE.png: pictures of basis functions, slices, spectra
// and lit spheres (icobrdf/plot/plots.hpp, docs/plots.md). Every picture is written atomically. The SOURCE is
// loaded (and models fitted) by icobrdf/pipeline/picture_source.hpp; plot/ draws what it is given. The flags are
// checked here, in the order the pictures used to check them, so that the first error names the flag.
#include <fmt/core.h>
#include <sys/stat.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli/commands.hpp"
#include "cli/option_checks.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/pipeline/picture_source.hpp"
#include "icobrdf/pipeline/reflectance_check.hpp"
#include "icobrdf/plot/picture_materials.hpp"
#include "icobrdf/plot/plots.hpp"

namespace icobrdf::cli {
namespace {

constexpr double kRadPerDeg = M_PI / 180.0;
constexpr int kMaxPlotOrder = 32;           // largest truncation order a slice or sphere fit is drawn at
constexpr std::size_t kMaxSliceColumns = 9;  // orders side by side in one slice picture
constexpr int kMinSphereSize = 16, kMaxSphereSize = 2048;

struct PlotArgs {
  std::string source, output, filter = "none", light = "45,135", shading = "auto";
  int order = 4, level = 4, size = 256, panel = 200, basis_panel = 0;
  std::vector<int> orders{0, 1, 2, 4, 6, 8};
  double theta_i = 45.0, phi_i = 0.0, sky_radiance = 0.3, exposure = 1.0;
  bool separate = false, sky = false, no_exact = false, json = false, strict = false;
};

// Level of the cells at whose directions a shaded spectrum's directional albedo is checked: 656 directions,
// enough to see a negative lobe of the orders a sphere is shaded with (<= 32), in milliseconds.
constexpr int kSphereAlbedoLevel = 3;

void report(const PlotArgs& a, nlohmann::json j) {
  if (a.json) std::cout << j.dump(2) << "\n";
  else std::cout << "wrote " << j["output"].get<std::string>() << "\n";
}

std::pair<double, double> parse_light(const std::string& s) {
  std::istringstream in(s);
  double t = NAN, p = NAN;
  char comma = 0;
  if (!(in >> t >> comma >> p) || comma != ',' || !(in >> std::ws).eof() || !(t >= 0 && t <= 180) || !std::isfinite(p))
    throw ArgumentError("--light '" + quoted_text(s) + "': expected THETA,PHI in degrees, 0 <= THETA <= 180, e.g. 45,135");
  return {t, p};
}

bool is_directory(const std::string& p) {
  struct stat st{};
  return ::stat(p.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

void check_basis_args(const PlotArgs& a) {
  if (!is_directory(a.output)) throw ArgumentError("-o " + a.output + ": not an existing directory");
}

void check_slice_args(const PlotArgs& a) {
  check_output_path(a.output, {a.source});
  if (a.orders.empty()) throw ArgumentError("--order: at least one truncation order is required");
  if (a.orders.size() > kMaxSliceColumns)
    throw ArgumentError(fmt::format("--order: at most {} orders side by side, found {}", kMaxSliceColumns, a.orders.size()));
}

plot::SphereRequest::Shading parse_shading(const std::string& s) {
  if (s == "auto") return plot::SphereRequest::Shading::Auto;
  if (s == "model") return plot::SphereRequest::Shading::Model;
  if (s == "spectrum") return plot::SphereRequest::Shading::Spectrum;
  throw ArgumentError("--shading: expected auto, model or spectrum, found '" + s + "'");
}

void add_basis_command(CLI::App* plot, const std::shared_ptr<PlotArgs>& a) {
  auto* basis = plot->add_subcommand("basis", "Every K_n^l up to --order on the Lambert disk (density + contours)");
  basis->add_option("--order,-n", a->order, "Largest order n")->capture_default_str()->check(CLI::Range(0, plot::kMaxBasisOrder));
  basis->add_option("--panel", a->basis_panel, "Disk diameter in pixels (default: from the order)")
      ->check(CLI::Range(plot::kMinBasisPanel, plot::kMaxBasisPanel));
  basis->add_flag("--separate", a->separate, "Also write one PNG per function, K_<n>_<l>.png");
  basis->add_option("-o,--output", a->output, "Output directory (must exist)")->required();
  basis->add_flag("--json", a->json, "Print the files written as JSON");
  basis->callback([a] {
    check_basis_args(*a);
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
  slice->add_option("--order,-n", a->orders, "Truncation orders shown side by side (at most 9)")->capture_default_str()->expected(1, 9)
      ->check(CLI::Range(0, kMaxPlotOrder));
  slice->add_option("--filter", a->filter, "Low-pass filter per order: none, fejer, lanczos, hann, gaussian[:width=W]")->capture_default_str();
  slice->add_option("--level,-l", a->level, "Grid level of the fit of a model")->capture_default_str()->check(CLI::Range(0, 8));
  slice->add_option("--panel", a->panel, "Disk diameter in pixels")->capture_default_str()->check(CLI::Range(64, 800));
  slice->add_flag("--no-exact", a->no_exact, "Do not add the model itself as a last column");
  slice->add_option("-o,--output", a->output, "Output PNG")->required();
  slice->add_flag("--json", a->json, "Print the figures as JSON");
  slice->callback([a] {
    plot::SliceRequest q;
    q.theta_i = a->theta_i * kRadPerDeg;
    q.phi_i = a->phi_i * kRadPerDeg;
    q.orders = a->orders;
    q.filter = parse_lowpass_filter(a->filter);
    q.panel = a->panel;
    q.exact = !a->no_exact;
    check_slice_args(*a);
    // A model is fitted once, at the largest order shown; a spectrum file is truncated.
    const int top_order = *std::max_element(a->orders.begin(), a->orders.end());
    const plot::SliceSource src = plot::slice_source(load_picture_material(a->source, top_order, a->level));
    if (top_order > src.spectrum.order)
      throw ArgumentError(fmt::format("--order {}: the spectrum of '{}' has order {}", top_order, a->source, src.spectrum.order));
    const auto f = plot::plot_slice(src, q, a->output);
    report(*a, {{"output", a->output}, {"width", f.width}, {"height", f.height}, {"scale", f.scale},
                {"quantity", f.g_form ? "g" : "f"}, {"columns", f.disks.size()}});
  });
}

void add_spectrum_command(CLI::App* plot, const std::shared_ptr<PlotArgs>& a) {
  auto* spec = plot->add_subcommand("spectrum", "IBSSS overview (paper Fig. 3) and the coefficient matrix of a spectrum file");
  spec->add_option("source", a->source, "SPECTRUM.h5[#material]")->required();
  spec->add_option("-o,--output", a->output, "Output PNG")->required();
  spec->add_flag("--json", a->json, "Print the figures as JSON");
  spec->callback([a] {
    const MaterialRef ref = split_material_ref(a->source);
    if (ref.path.size() < 4 || ref.path.compare(ref.path.size() - 3, 3, ".h5") != 0)
      throw ArgumentError("plot spectrum '" + quoted_text(a->source) + "': expected SPECTRUM.h5[#material]");
    const Spectrum s = read_spectrum_file(ref.path, ref.name);
    check_output_path(a->output, {a->source});
    const auto f = plot::plot_spectrum(s, a->source, a->output);
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
  sphere->add_option("--order,-n", a->orders, "Order of the fit when shading from a spectrum (one value)")->expected(1)->check(CLI::Range(0, kMaxPlotOrder));
  sphere->add_option("--level,-l", a->level, "Grid level of that fit")->capture_default_str()->check(CLI::Range(0, 8));
  sphere->add_option("--shading", a->shading, "auto (model when it has no delta part), model, or spectrum")->capture_default_str();
  sphere->add_option("-o,--output", a->output, "Output PNG")->required();
  sphere->add_flag("--json", a->json, "Print the figures as JSON");
  sphere->add_flag("--strict", a->strict, "Negative reflectance of a material is an error (default: a warning)");
  sphere->callback([a, sphere] {
    plot::SphereRequest q;
    const auto [t, p] = parse_light(a->light);
    q.light_theta = t * kRadPerDeg;
    q.light_phi = p * kRadPerDeg;
    q.sky = a->sky ? a->sky_radiance : 0.0;
    q.exposure = a->exposure;
    q.size = a->size;
    constexpr int kDefaultSphereOrder = 8;
    const int order = sphere->count("--order") ? a->orders.front() : kDefaultSphereOrder;
    check_output_path(a->output, {a->source});
    q.shading = parse_shading(a->shading);
    const auto materials = plot::load_sphere_materials(a->source, q.shading, order, a->level, "--shading model");
    // A sphere shaded from a spectrum with negative albedo would show it clipped to black without a word.
    const Grid albedo_grid = build_equal_area_grid(kSphereAlbedoLevel);
    for (const auto& m : materials)
      if (m.spectrum) check_fitted_albedo(*m.spectrum, albedo_grid, "plot sphere '" + quoted_text(m.name) + "'", {a->strict, &std::cerr});
    const auto f = plot::plot_sphere(a->source, materials, q, a->output);
    report(*a, {{"output", a->output}, {"width", f.width}, {"height", f.height}, {"spheres", f.names}});
  });
}

void add_plot_command(CLI::App& app) {
  auto a = std::make_shared<PlotArgs>();
  auto* plot = app.add_subcommand("plot", "Draw PNG pictures: basis functions, slices, spectra, lit spheres");
  plot->require_subcommand(1);
  add_basis_command(plot, a);
  add_slice_command(plot, a);
  add_spectrum_command(plot, a);
  add_sphere_command(plot, a);
}

const CommandRegistrar kCmdPlotRegistrar("plot", add_plot_command);

}  // namespace
}  // namespace icobrdf::cli
