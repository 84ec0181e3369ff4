// icobrdf plot basis|slice|spectrum|sphere ... -o FILE.png: pictures of basis functions, slices, spectra
// and lit spheres (plot/plots.hpp, docs/plots.md). Every picture is written atomically.
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>
#include <memory>
#include <sstream>

#include "cli/commands.hpp"
#include "core/error.hpp"
#include "core/lowpass_filter.hpp"
#include "io/bank_file.hpp"
#include "io/spectrum_file.hpp"
#include "plot/plots.hpp"

namespace icobrdf::cli {
namespace {

constexpr double kRadPerDeg = 3.14159265358979323846 / 180.0;

struct PlotArgs {
  std::string source, output, filter = "none", light = "45,135", shading = "auto";
  int order = 4, level = 4, size = 256, panel = 200, basis_panel = 0;
  std::vector<int> orders{0, 1, 2, 4, 6, 8};
  double theta_i = 45.0, phi_i = 0.0, sky_radiance = 0.3, exposure = 1.0;
  bool separate = false, sky = false, no_exact = false, json = false;
};

void report(const PlotArgs& a, nlohmann::json j) {
  if (a.json) std::cout << j.dump(2) << "\n";
  else std::cout << "wrote " << j["output"].get<std::string>() << "\n";
}

std::pair<double, double> parse_light(const std::string& s) {
  std::istringstream in(s);
  double t = NAN, p = NAN;
  char comma = 0;
  if (!(in >> t >> comma >> p) || comma != ',' || !(in >> std::ws).eof() || !std::isfinite(t) || !std::isfinite(p))
    throw ArgumentError("--light '" + s + "': expected THETA,PHI in degrees, e.g. 45,135");
  return {t, p};
}

void add_plot_command(CLI::App& app) {
  auto a = std::make_shared<PlotArgs>();
  auto* plot = app.add_subcommand("plot", "Draw PNG pictures: basis functions, slices, spectra, lit spheres");
  plot->require_subcommand(1);

  auto* basis = plot->add_subcommand("basis", "Every K_n^l up to --order on the Lambert disk (density + contours)");
  basis->add_option("--order,-n", a->order, "Largest order n")->capture_default_str()->check(CLI::Range(0, 16));
  basis->add_option("--panel", a->basis_panel, "Disk diameter in pixels (default: from the order)");
  basis->add_flag("--separate", a->separate, "Also write one PNG per function, K_<n>_<l>.png");
  basis->add_option("-o,--output", a->output, "Output directory (must exist)")->required();
  basis->add_flag("--json", a->json, "Print the files written as JSON");
  basis->callback([a] {
    const auto files = plot::plot_basis(a->order, a->output, a->separate, a->basis_panel);
    if (a->json) std::cout << nlohmann::json{{"files", files}}.dump(2) << "\n";
    else for (const auto& f : files) std::cout << "wrote " << f << "\n";
  });

  auto* slice = plot->add_subcommand("slice", "Remitted distribution for one incident direction, several truncation orders");
  slice->add_option("source", a->source, "SOURCE: model:NAME[:key=value,...] or FILE.h5[#material]")->required();
  slice->add_option("--theta-i", a->theta_i, "Polar angle of incidence [deg], 0 <= theta_i < 90")->capture_default_str();
  slice->add_option("--phi-i", a->phi_i, "Azimuth of incidence [deg]")->capture_default_str();
  slice->add_option("--order,-n", a->orders, "Truncation orders shown side by side (at most 9)")->capture_default_str()->expected(1, 9);
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
    q.level = a->level;
    q.panel = a->panel;
    q.exact = !a->no_exact;
    const auto f = plot::plot_slice(a->source, q, a->output);
    report(*a, {{"output", a->output}, {"width", f.width}, {"height", f.height}, {"scale", f.scale},
                {"quantity", f.g_form ? "g" : "f"}, {"columns", f.disks.size()}});
  });

  auto* spec = plot->add_subcommand("spectrum", "IBSSS overview (paper Fig. 3) and the coefficient matrix of a spectrum file");
  spec->add_option("source", a->source, "SPECTRUM.h5[#material]")->required();
  spec->add_option("-o,--output", a->output, "Output PNG")->required();
  spec->add_flag("--json", a->json, "Print the figures as JSON");
  spec->callback([a] {
    const MaterialRef ref = split_material_ref(a->source);
    if (ref.path.size() < 4 || ref.path.compare(ref.path.size() - 3, 3, ".h5") != 0)
      throw ArgumentError("plot spectrum '" + a->source + "': expected SPECTRUM.h5[#material]");
    const Spectrum s = read_spectrum_file(ref.path, ref.name);
    const auto f = plot::plot_spectrum(s, a->source, a->output);
    report(*a, {{"output", a->output}, {"width", f.width}, {"height", f.height}, {"order", s.order}, {"matrix", f.matrix_drawn}});
  });

  auto* sphere = plot->add_subcommand("sphere", "A sphere of the material lit by a distant light (a grid for a bank)");
  sphere->add_option("source", a->source, "SOURCE: model:..., FILE.h5[#material], or BANK.h5 (all materials)")->required();
  sphere->add_option("--light", a->light, "Light direction THETA,PHI [deg] in the camera frame (theta from the viewing axis)")
      ->capture_default_str();
  sphere->add_flag("--sky", a->sky, "Add a uniform sky (radiance --sky-radiance)");
  sphere->add_option("--sky-radiance", a->sky_radiance, "Sky radiance with --sky")->capture_default_str();
  sphere->add_option("--exposure", a->exposure, "Radiance shown as white")->capture_default_str();
  sphere->add_option("--size", a->size, "Sphere diameter in pixels")->capture_default_str();
  sphere->add_option("--order,-n", a->orders, "Order of the fit when shading from a spectrum (one value)")->expected(1);
  sphere->add_option("--level,-l", a->level, "Grid level of that fit")->capture_default_str()->check(CLI::Range(0, 8));
  sphere->add_option("--shading", a->shading, "auto (model when it has no delta part), model, or spectrum")->capture_default_str();
  sphere->add_option("-o,--output", a->output, "Output PNG")->required();
  sphere->add_flag("--json", a->json, "Print the figures as JSON");
  sphere->callback([a, sphere] {
    plot::SphereRequest q;
    const auto [t, p] = parse_light(a->light);
    q.light_theta = t * kRadPerDeg;
    q.light_phi = p * kRadPerDeg;
    q.sky = a->sky ? a->sky_radiance : 0.0;
    q.exposure = a->exposure;
    q.size = a->size;
    q.order = sphere->count("--order") ? a->orders.front() : 8;
    if (q.order < 0 || q.order > 32) throw ArgumentError(fmt::format("--order {}: expected 0..32", q.order));
    q.level = a->level;
    q.shading = a->shading;
    const auto f = plot::plot_sphere(a->source, q, a->output);
    report(*a, {{"output", a->output}, {"width", f.width}, {"height", f.height}, {"spheres", f.names}});
  });
}

const CommandRegistrar kRegistrar("plot", add_plot_command);

}  // namespace
}  // namespace icobrdf::cli
