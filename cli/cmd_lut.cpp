// LUT commands:
//   icobrdf lut SOURCE --level L [--cosine] [--sampling average|centre] [--float32] [--order N] -o LUT.h5
//   icobrdf smooth LUT.h5[#MATERIAL] --order N [--filter NAME] [--float32] -o OUT.h5     (S F S^T)
//   icobrdf albedo SOURCE [--black-sky DEG[,DEG...]] [--white-sky] [--curve] [--json] [--strict]  (icobrdf/pipeline/source_albedo.hpp)
//   icobrdf albedo LUT.h5[#MATERIAL] [--json] [--strict]                                (white furnace)
// lut and albedo refuse Inf / NaN and report negative f or albedo (icobrdf/pipeline/reflectance_check.hpp).
// LUT files: icobrdf/io/lut_file.hpp.
#include <nlohmann/json.hpp>

#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/output_path.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/lut_material.hpp"
#include "icobrdf/pipeline/source_albedo.hpp"

namespace icobrdf::cli {
namespace {

struct LutArgs {
  LutRequest lut;  // lut's options
  std::string input, output, filter = "none", sampling = "average";  // smooth's, and lut's sampling name
  int order = 8;
  bool float32 = false;
};

void run_lut(LutRequest q, const std::string& sampling) {
  check_output_path(q.output, {q.source});
  require_storable_source(q.source);
  const auto named = lut_sampling_named(sampling);
  if (!named) throw ArgumentError("--sampling: expected 'average' or 'centre', found '" + quoted_text(sampling) + "'");
  q.sampling = *named;
  std::cout << lut_written_text(write_source_lut(q, &std::cerr), q.output);
}

void run_smooth(const LutArgs& a) {
  check_output_path(a.output, {a.input});
  std::cout << smoothed_lut_text(write_smoothed_lut(a.input, a.output, a.order, a.filter, a.float32), a.output, a.order);
}

void run_albedo(const AlbedoRequest& q, bool json) {
  const nlohmann::json j = albedo_json(q, &std::cerr);
  std::cout << (json ? j.dump(2) + "\n" : albedo_text(j));
}

void add_lut_commands(CLI::App& app) {
  auto a = std::make_shared<LutArgs>();
  auto* lut = app.add_subcommand("lut", "Sample a model into a cells x cells LUT on the equal-area grid (HDF5)");
  lut->add_option("source", a->lut.source, "SOURCE: model:NAME[:key=value,...], or a bank material FILE.h5#NAME of any representation, or measured data")->required();
  lut->add_option("--level,-l", a->lut.level, "Tessellation level")->capture_default_str()->check(CLI::Range(0, 6));
  lut->add_option("--order,-n", a->lut.order, "Order of the spectrum stored with the LUT")->capture_default_str()->check(CLI::Range(0, 128));
  lut->add_flag("--cosine", a->lut.cosine, "Tabulate g = f cos(theta_i) (always for delta models)");
  lut->add_option("--sampling", a->sampling, "average (cell cubature) or centre")->capture_default_str();
  lut->add_flag("--float32", a->lut.float32, "Store the LUT as float32 (the rounding error is recorded)");
  lut->add_option("--name", a->lut.name, "Material name in the file")->capture_default_str();
  lut->add_option("-o,--output", a->lut.output, "Output file (.h5)")->required();
  lut->add_flag("--strict", a->lut.strict, "Negative f or albedo (non-physical) is an error, not a warning");
  lut->callback([a] { run_lut(a->lut, a->sampling); });

  auto s = std::make_shared<LutArgs>();
  auto* smooth = app.add_subcommand("smooth", "Smooth a LUT: S F S^T with truncation or a low-pass filter");
  smooth->add_option("lut", s->input, "LUT.h5[#MATERIAL]")->required();
  smooth->add_option("--order,-n", s->order, "Truncation order")->capture_default_str()->check(CLI::Range(0, 128));
  smooth->add_option("--filter", s->filter, "none, fejer, lanczos, hann, gaussian[:width=W]")->capture_default_str();
  smooth->add_flag("--float32", s->float32, "Store the smoothed LUT as float32");
  smooth->add_option("-o,--output", s->output, "Output file (.h5)")->required();
  smooth->callback([s] { run_smooth(*s); });

  auto b = std::make_shared<AlbedoRequest>();
  auto json = std::make_shared<bool>(false);
  auto* albedo = app.add_subcommand("albedo", "Black-sky and white-sky albedos of a SOURCE; a LUT's directional albedo and white-furnace check");
  albedo->add_option("source", b->input, "SOURCE, or LUT.h5[#MATERIAL] (without the options below: the LUT's figures)")->required();
  albedo->add_option("--black-sky", b->black_sky_deg, "Black-sky albedo at these solar zeniths (DEG[,DEG...])")->delimiter(',');
  albedo->add_flag("--white-sky", b->white_sky, "White-sky (bihemispherical) albedo");
  albedo->add_flag("--curve", b->curve, "The directional (black-sky) albedo at every degree from 0 to 89");
  albedo->add_flag("--json", *json, "JSON output");
  albedo->add_flag("--strict", b->strict, "A negative albedo (non-physical) is an error, not a warning");
  albedo->callback([b, json] { run_albedo(*b, *json); });
}

const CommandRegistrar kRegLut("lut", add_lut_commands);

}  // namespace
}  // namespace icobrdf::cli
