#include "icobrdf/plot/picture_materials.hpp"

#include <iostream>
#include <utility>

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
  if (!names.empty() && shading == Shading::Model) throw ArgumentError(model_shading_label + ": a bank holds spectra only");
  for (const auto& n : names) {
    PictureMaterial m = stored_bank_material(text, n);  // a material with a lobe comes as its values
    materials.push_back({n, std::move(m.spectrum), std::move(m.exact), m.exact_channels});
  }
  if (!names.empty()) return materials;
  // A source with values everywhere (a model without delta parts, a measured file, a stored material with a
  // half-angle lobe) is shaded from them, unfitted, unless told to shade from a spectrum.
  PictureMaterial m = load_picture_material(text, order, level, shading != Shading::Spectrum);
  if (shading == Shading::Model && !m.exact)
    throw ArgumentError(model_shading_label + ": needs values known everywhere (no delta part, not scattered samples), found '" +
                        quoted_text(text) + "'");
  if (m.exact && shading != Shading::Spectrum) materials.push_back({text, std::nullopt, std::move(m.exact), m.exact_channels});
  else materials.push_back({text, std::move(m.spectrum), {}, 1});
  return materials;
}

void check_sphere_albedo(const std::vector<SphereMaterial>& materials, bool strict) {
  constexpr int kSphereAlbedoLevel = 3;  // 656 directions (header)
  const Grid grid = build_equal_area_grid(kSphereAlbedoLevel);
  for (const auto& m : materials)
    if (m.spectrum) check_fitted_albedo(*m.spectrum, grid, "plot sphere '" + quoted_text(m.name) + "'", {strict, &std::cerr});
}

}  // namespace icobrdf::plot
