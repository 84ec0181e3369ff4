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
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/lut_material.hpp"

namespace icobrdf::cli {
namespace {

struct LutArgs {
  std::string source, input, output, filter = "none", sampling = "average", name = "lut";
  int level = 4, order = 8;
  bool cosine = false, float32 = false, json = false, strict = false;
};

void run_lut(const LutArgs& a) {
  check_output_path(a.output, {a.source});
  require_storable_source(a.source);
  const auto named = lut_sampling_named(a.sampling);
  if (!named) throw ArgumentError("--sampling: expected 'average' or 'centre', found '" + quoted_text(a.sampling) + "'");
  LutRequest q;
  q.source = a.source;
  q.output = a.output;
  q.name = a.name;
  q.level = a.level;
  q.order = a.order;
  q.cosine = a.cosine;
  q.float32 = a.float32;
  q.strict = a.strict;
  q.sampling = *named;
  const LutWritten w = write_source_lut(q, &std::cerr);
  std::cout << fmt::format("{}: {} x {} LUT of {} ({}), max directional albedo {:.6g}\n", a.output, w.cells, w.cells, w.label,
                           w.cosine ? "g = f cos(theta_i)" : "f", w.max_albedo);
}

void run_smooth(const LutArgs& a) {
  check_output_path(a.output, {a.input});
  const SmoothedLut s = write_smoothed_lut(a.input, a.output, a.order, a.filter, a.float32);
  std::cout << fmt::format("{}: LUT '{}' smoothed to order {} with filter {}\n", a.output, s.name, a.order, s.filter);
}

void run_albedo(const LutArgs& a) {
  const nlohmann::json j = lut_albedo_json(a.input, a.strict, &std::cerr);
  if (a.json) {
    std::cout << j.dump(2) << "\n";
    return;
  }
  const nlohmann::json& ch = j["channels"];
  std::cout << fmt::format("{} '{}' ({} cells):\n", a.input, j["material"].get<std::string>(), j["cells"].get<int>());
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
