#pragma once
// The materials a picture draws, from a SOURCE as the user names it (icobrdf/pipeline/picture_source.hpp loads
// it, and fits a model): the source of a slice picture, and the materials of a sphere picture.
#include <string>
#include <vector>

#include "icobrdf/pipeline/picture_source.hpp"
#include "icobrdf/plot/plots.hpp"

namespace icobrdf::plot {

// A loaded material as a slice picture's source: its spectrum and, when it has one, the model's values.
SliceSource slice_source(PictureMaterial m);

// Every material of a bank of several, or the one material of any other SOURCE: as its values (unfitted)
// when they are known everywhere (a model without delta parts, a measured file) and `shading` allows, else as a spectrum (stored, or fitted at `order` on
// the equal-area grid of `level`). A stored material with a half-angle lobe comes with its values: shaded from
// them unless the shading is Spectrum; with the Model shading every stored material (a bank's, FILE.h5#material)
// is shaded from its values (modes: their reconstruction, icobrdf/pipeline/picture_source.hpp add_stored_values).
// ArgumentError, starting with `model_shading_label` (the caller's name for the Model shading), when the Model
// shading is asked of a SOURCE without such values (a model with delta parts, scattered samples).
std::vector<SphereMaterial> load_sphere_materials(const std::string& text, SphereRequest::Shading shading, int order, int level,
                                                  const std::string& model_shading_label);

// A sphere shaded from a spectrum or from values with negative albedo would show it clipped to black without a
// word: the directional albedo of each material shaded from a spectrum is checked at the 656 directions of the
// level-3 cells (enough to see a negative lobe of the orders a sphere is shaded with, <= 32, in milliseconds),
// that of a material shaded from its values (a model, a measured file) by a cell sum at the 164 directions of
// the level-2 cells; either is reported on stderr, or with `strict` thrown
// (icobrdf/pipeline/reflectance_check.hpp).
void check_sphere_albedo(const std::vector<SphereMaterial>& materials, bool strict);

}  // namespace icobrdf::plot
