#include "icobrdf/pipeline/lut_material.hpp"

#include <fmt/core.h>

#include <cmath>
#include <memory>
#include <utility>
#include <vector>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/core/fit/spectral_fit.hpp"
#include "icobrdf/core/projection/reflection.hpp"
#include "icobrdf/io/lut_file.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/pipeline/reflectance_check.hpp"
#include "icobrdf/pipeline/resource_estimate.hpp"
#include "icobrdf/pipeline/source_model.hpp"

namespace icobrdf {
namespace {

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

}  // namespace

LutWritten write_source_lut(const LutRequest& a, std::ostream* warnings) {
  LutWritten out;
  std::vector<std::string> channel_names;
  const auto model = model_of_source(a.source, &out.label, &channel_names);
  auto grid = std::make_shared<const Grid>(build_equal_area_grid(a.level));
  out.cosine = a.cosine || !model->delta_parts().empty();
  const std::int64_t cells = equal_area_cells(a.level);
  require_storable_lut(cells, model->channels(), a.float32, a.output);
  require_lut_memory(a.level, a.order, model->channels(), a.float32, "lut of " + out.label);
  // Cell averages with a degree-2 rule on the same cells: the LUT's own sampling, independent of B's rule.
  const Grid sampling_grid = a.sampling == LutSampling::CellAverage ? build_equal_area_grid(a.level, kLutSamplingDegree) : *grid;
  Lut lut = build_lut(*model, sampling_grid, out.cosine, a.sampling);
  check_lut(lut.channels, out.cosine, *grid, a.output + ": LUT of " + out.label, {a.strict, warnings});
  FitOptions o;
  o.order = a.order;
  o.cosine = out.cosine;
  const auto ctx = make_projection_context(grid, a.order);
  out.max_albedo = white_furnace(lut.channels[0], out.cosine, *grid).max_albedo;
  out.cells = grid->cells();
  auto rec = lut_record(a.name, std::move(lut), out.label, ctx, o, a.float32);
  rec.spectrum.channel_names = channel_names;
  write_lut_file(a.output, *grid, std::move(rec));
  return out;
}

SmoothedLut write_smoothed_lut(const std::string& input, const std::string& output, int order, const std::string& filter, bool float32) {
  auto [grid, rec] = read_lut_file(input);
  FitOptions o;
  o.order = order;
  o.filter = parse_lowpass_filter(filter);
  const auto ctx = make_projection_context(grid, order);
  Lut smoothed;
  smoothed.cosine = rec.spectrum.cosine;
  for (const auto& f : rec.lut) smoothed.channels.push_back(smooth_lut(ctx.basis, ctx.projection, f, o.filter));
  o.cosine = smoothed.cosine;
  auto out = lut_record(rec.name, std::move(smoothed), rec.spectrum.source, ctx, o, float32);
  out.spectrum.filter = o.filter.name();
  write_lut_file(output, *grid, std::move(out));
  return {rec.name, o.filter.name()};
}

nlohmann::json lut_albedo_json(const std::string& input, bool strict, std::ostream* warnings) {
  auto [grid, rec] = read_lut_file(input);
  check_lut(rec.lut, rec.spectrum.cosine, *grid, input + " material '" + rec.name + "'", {strict, warnings});
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
  return {{"file", input}, {"material", rec.name}, {"cells", grid->cells()}, {"channels", ch}};
}

std::string lut_written_text(const LutWritten& w, const std::string& output) {
  return fmt::format("{}: {} x {} LUT of {} ({}), max directional albedo {:.6g}\n", output, w.cells, w.cells, w.label,
                     w.cosine ? "g = f cos(theta_i)" : "f", w.max_albedo);
}

std::string smoothed_lut_text(const SmoothedLut& s, const std::string& output, int order) {
  return fmt::format("{}: LUT '{}' smoothed to order {} with filter {}\n", output, s.name, order, s.filter);
}

}  // namespace icobrdf
