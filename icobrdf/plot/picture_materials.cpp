#include "icobrdf/plot/picture_materials.hpp"

#include <iostream>
#include <optional>
#include <utility>

#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/core/projection/reflection.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/mesh/tessellation.hpp"
#include "icobrdf/pipeline/reflectance_check.hpp"

namespace icobrdf::plot {

SliceSource slice_source(PictureMaterial m) {
  return SliceSource{std::move(m.name), std::move(m.spectrum), std::move(m.exact), std::move(m.exact_kind)};
}

std::vector<SphereMaterial> load_sphere_materials(const std::string& text, SphereRequest::Shading shading, int order, int level,
                                                  const std::string& model_shading_label) {
  using Shading = SphereRequest::Shading;
  const std::vector<std::string> names = several_bank_materials(text);
  std::vector<SphereMaterial> materials;
  for (const auto& n : names) {
    PictureMaterial m = stored_bank_material(text, n);  // a material with a lobe comes as its values
    if (shading == Shading::Model) add_stored_values(m);  // modes: their reconstruction
    materials.push_back({n, std::move(m.spectrum), std::move(m.exact), m.exact_channels});
  }
  if (!names.empty()) return materials;
  // A source with values everywhere (a model without delta parts, a measured file, a stored material with a
  // half-angle lobe) is shaded from them, unfitted, unless told to shade from a spectrum.
  // Shading from the model needs its values: nothing is fitted before a source without them is refused.
  PictureMaterial m = load_picture_material(text, order, level, shading != Shading::Spectrum, shading != Shading::Model);
  if (shading == Shading::Model) add_stored_values(m);  // a stored spectrum: its values
  if (shading == Shading::Model && !m.exact)
    throw ArgumentError(model_shading_label + ": needs values known everywhere (no delta part, not scattered samples), found '" +
                        quoted_text(text) + "'");
  if (m.exact && shading != Shading::Spectrum) materials.push_back({text, std::nullopt, std::move(m.exact), m.exact_channels});
  else materials.push_back({text, std::move(m.spectrum), {}, 1});
  return materials;
}

namespace {

// The directional albedo of a material's values at the grid's cell directions (cells x channels): the LUT of
// the values at the cell centres, summed over the outgoing cells with their mean cosines and solid angles
// (icobrdf/core/projection/reflection.hpp).
Eigen::MatrixXd value_albedo(const SphereMaterial& m, const Grid& grid) {
  const FunctionModel values(
      m.model_channels, [&m](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) { out = m.model(wi, wr); },
      m.name, false, false);
  const Lut lut = build_lut(values, grid, false, LutSampling::CellCentre);
  Eigen::MatrixXd albedo(grid.directions.rows(), values.channels());
  for (int c = 0; c < values.channels(); ++c) albedo.col(c) = directional_albedo(lut.channels[static_cast<size_t>(c)], false, grid);
  return albedo;
}

}  // namespace

void check_sphere_albedo(const std::vector<SphereMaterial>& materials, bool strict) {
  constexpr int kSphereAlbedoLevel = 3;  // 656 directions (header)
  constexpr int kValueAlbedoLevel = 2;   // 164 directions, 26,896 pairs: a few ms for a model, ~0.1 s for a measured file
  const Grid grid = build_equal_area_grid(kSphereAlbedoLevel);
  std::optional<Grid> coarse;
  for (const auto& m : materials) {
    const std::string where = "plot sphere '" + quoted_text(m.name) + "'";
    if (m.spectrum) {
      check_fitted_albedo(*m.spectrum, grid, where, {strict, &std::cerr});
    } else if (m.model) {
      if (!coarse) coarse = build_equal_area_grid(kValueAlbedoLevel);
      check_reflectance(value_albedo(m, *coarse), where, "the values' albedo at the cell directions", "directional albedo", {strict, &std::cerr});
    }
  }
}

}  // namespace icobrdf::plot
