// LUT commands:
//   icobrdf lut SOURCE --level L [--cosine] [--sampling average|centre] [--float32] [--order N] -o LUT.h5
//   icobrdf smooth LUT.h5[#MATERIAL] --order N [--filter NAME] [--float32] -o OUT.h5     (S F S^T)
//   icobrdf albedo LUT.h5[#MATERIAL] [--json] [--strict]                                (white furnace)
// lut and albedo refuse Inf / NaN and report negative f or albedo (icobrdf/pipeline/reflectance_check.hpp).
// LUT files: icobrdf/io/lut_file.hpp.
#include <fmt/core.h>
#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/projection/reflection.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/pipeline/reflectance_check.hpp"
#include "icobrdf/pipeline/resource_estimate.hpp"
#include "icobrdf/pipeline/source_model.hpp"
#include "icobrdf/io/lut_file.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/mesh/tessellation.hpp"

namespace icobrdf::cli {
namespace {

struct LutArgs {
  std::string source, input, output, filter = "none", sampling = "average", name = "lut";
  int level = 4, order = 8;
  bool cosine = false, float32 = false, json = false, strict = false;
};

// Takes the LUT's channels (moved, not copied: a level-5 LUT is 850 MB per channel).
MaterialRecord lut_record(const std::string& name, Lut&& lut, const std::string& source, const ProjectionContext& ctx,
                          const FitOptions& o, bool float32) {
  MaterialRecord rec;
  rec.name = name;
  rec.spectrum = fit_lut(lut, source, ctx, o);
  rec.lut = std::move(lut.channels);
  rec.lut_float32 = float32;
  return rec;
}

void run_lut(const LutArgs& a) {
  check_output_path(a.output, {a.source});
  require_storable_source(a.source);
  std::string label;
  std::vector<std::string> channel_names;
  const auto model = model_of_source(a.source, &label, &channel_names);
  auto grid = std::make_shared<const Grid>(build_equal_area_grid(a.level));
  const auto named = lut_sampling_named(a.sampling);
  if (!named) throw ArgumentError("--sampling: expected 'average' or 'centre', found '" + quoted_text(a.sampling) + "'");
  const LutSampling sampling = *named;
  const bool cosine = a.cosine || !model->delta_parts().empty();
  const std::int64_t cells = equal_area_cells(a.level);
  require_storable_lut(cells, model->channels(), a.float32, a.output);
  require_lut_memory(a.level, a.order, model->channels(), a.float32, "lut of " + label);
  // Cell averages with a degree-2 rule on the same cells: the LUT's own sampling, independent of B's rule.
  const Grid sampling_grid = sampling == LutSampling::CellAverage ? build_equal_area_grid(a.level, kLutSamplingDegree) : *grid;
  Lut lut = build_lut(*model, sampling_grid, cosine, sampling);
  check_lut(lut.channels, cosine, *grid, a.output + ": LUT of " + label, {a.strict, &std::cerr});
  FitOptions o;
  o.order = a.order;
  o.cosine = cosine;
  const auto ctx = make_projection_context(grid, a.order);
  const auto wf = white_furnace(lut.channels[0], cosine, *grid);
  auto rec = lut_record(a.name, std::move(lut), label, ctx, o, a.float32);
  rec.spectrum.channel_names = channel_names;
  write_lut_file(a.output, *grid, std::move(rec));
  std::cout << fmt::format("{}: {} x {} LUT of {} ({}), max directional albedo {:.6g}\n", a.output, grid->cells(), grid->cells(),
                           label, cosine ? "g = f cos(theta_i)" : "f", wf.max_albedo);
}

void run_smooth(const LutArgs& a) {
  check_output_path(a.output, {a.input});
  auto [grid, rec] = read_lut_file(a.input);
  FitOptions o;
  o.order = a.order;
  o.filter = parse_lowpass_filter(a.filter);
  const auto ctx = make_projection_context(grid, a.order);
  Lut smoothed;
  smoothed.cosine = rec.spectrum.cosine;
  for (const auto& f : rec.lut) smoothed.channels.push_back(smooth_lut(ctx.basis, ctx.projection, f, o.filter));
  o.cosine = smoothed.cosine;
  auto out = lut_record(rec.name, std::move(smoothed), rec.spectrum.source, ctx, o, a.float32);
  out.spectrum.filter = o.filter.name();
  write_lut_file(a.output, *grid, std::move(out));
  std::cout << fmt::format("{}: LUT '{}' smoothed to order {} with filter {}\n", a.output, rec.name, a.order, o.filter.name());
}

void run_albedo(const LutArgs& a) {
  auto [grid, rec] = read_lut_file(a.input);
  check_lut(rec.lut, rec.spectrum.cosine, *grid, a.input + " material '" + rec.name + "'", {a.strict, &std::cerr});
  nlohmann::json ch = nlohmann::json::array();
  for (const auto& f : rec.lut) {
    const auto wf = white_furnace(f, rec.spectrum.cosine, *grid);
    const auto al = directional_albedo(f, rec.spectrum.cosine, *grid);
    const Angles worst = angles_from_direction(grid->directions.row(wf.worst_cell).transpose());
    const double theta = worst.theta * 180 / M_PI, phi = worst.phi * 180 / M_PI;
    ch.push_back({{"max_albedo", wf.max_albedo}, {"min_albedo", al.minCoeff()}, {"mean_albedo", wf.mean_albedo},
                  {"worst_cell", wf.worst_cell}, {"worst_theta_deg", theta}, {"worst_phi_deg", phi},
                  {"energy_conserving", wf.max_albedo <= 1.0}});
  }
  if (a.json) {
    std::cout << nlohmann::json{{"file", a.input}, {"material", rec.name}, {"cells", grid->cells()}, {"channels", ch}}.dump(2) << "\n";
    return;
  }
  std::cout << fmt::format("{} '{}' ({} cells):\n", a.input, rec.name, grid->cells());
  for (size_t c = 0; c < ch.size(); ++c)
    std::cout << fmt::format("  channel {}: directional albedo max {:.6g} (at theta {:.1f} deg, phi {:.1f} deg), min {:.6g}, mean {:.6g}: {}\n", c,
                             ch[c]["max_albedo"].get<double>(), ch[c]["worst_theta_deg"].get<double>(), ch[c]["worst_phi_deg"].get<double>(),
                             ch[c]["min_albedo"].get<double>(), ch[c]["mean_albedo"].get<double>(),
                             ch[c]["min_albedo"].get<double>() < 0 ? "NON-PHYSICAL (negative albedo)"
                             : ch[c]["energy_conserving"].get<bool>() ? "passes the white furnace" : "FAILS the white furnace (albedo > 1)");
}

void add_lut_commands(CLI::App& app) {
  auto a = std::make_shared<LutArgs>();
  auto* lut = app.add_subcommand("lut", "Sample a model into a cells x cells LUT on the equal-area grid (HDF5)");
  lut->add_option("source", a->source, "SOURCE: model:NAME[:key=value,...], or a bank material FILE.h5#NAME of any representation, or measured data")->required();
  lut->add_option("--level,-l", a->level, "Tessellation level")->capture_default_str()->check(CLI::Range(0, 6));
  lut->add_option("--order,-n", a->order, "Order of the spectrum stored with the LUT")->capture_default_str()->check(CLI::Range(0, 128));
  lut->add_flag("--cosine", a->cosine, "Tabulate g = f cos(theta_i) (always for delta models)");
  lut->add_option("--sampling", a->sampling, "average (cell cubature) or centre")->capture_default_str();
  lut->add_flag("--float32", a->float32, "Store the LUT as float32 (the rounding error is recorded)");
  lut->add_option("--name", a->name, "Material name in the file")->capture_default_str();
  lut->add_option("-o,--output", a->output, "Output file (.h5)")->required();
  lut->add_flag("--strict", a->strict, "Negative f or albedo (non-physical) is an error, not a warning");
  lut->callback([a] { run_lut(*a); });

  auto s = std::make_shared<LutArgs>();
  auto* smooth = app.add_subcommand("smooth", "Smooth a LUT: S F S^T with truncation or a low-pass filter");
  smooth->add_option("lut", s->input, "LUT.h5[#MATERIAL]")->required();
  smooth->add_option("--order,-n", s->order, "Truncation order")->capture_default_str()->check(CLI::Range(0, 128));
  smooth->add_option("--filter", s->filter, "none, fejer, lanczos, hann, gaussian[:width=W]")->capture_default_str();
  smooth->add_flag("--float32", s->float32, "Store the smoothed LUT as float32");
  smooth->add_option("-o,--output", s->output, "Output file (.h5)")->required();
  smooth->callback([s] { run_smooth(*s); });

  auto b = std::make_shared<LutArgs>();
  auto* albedo = app.add_subcommand("albedo", "Directional albedo of a LUT and the white-furnace check");
  albedo->add_option("lut", b->input, "LUT.h5[#MATERIAL]")->required();
  albedo->add_flag("--json", b->json, "JSON output");
  albedo->add_flag("--strict", b->strict, "A negative albedo (non-physical) is an error, not a warning");
  albedo->callback([b] { run_albedo(*b); });
}

const CommandRegistrar kRegLut("lut", add_lut_commands);

}  // namespace
}  // namespace icobrdf::cli
