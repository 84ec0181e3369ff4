#pragma once
// A SOURCE made ready for a picture (`icobrdf plot ...`): a spectrum file as stored, or any other SOURCE
// fitted through fit_source (icobrdf/pipeline/fit_source.hpp) the way `icobrdf fit` fits it (cell-averaged
// sampling on the equal-area grid, g form when the source has delta parts), and a source whose values are
// known everywhere (a model without delta parts, a measured table or file such as MERL or RGL, a stored
// material with a half-angle lobe) also as itself. A picture that only needs those values asks for no fit:
// a measured file is then evaluated directly at the picture's directions (seconds, not a projection).
// plot/ draws what it is given; cli/ words the flag errors.
#include <Eigen/Core>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/spectrum/spectrum.hpp"

namespace icobrdf {

struct PictureMaterial {
  std::string name;                  // the SOURCE as the user named it, or the bank's material name
  std::optional<Spectrum> spectrum;  // stored or fitted; empty when only the model is asked for
  // The model itself, values (pairs x channels) for incident/remitted directions; empty: none.
  std::function<Eigen::MatrixXd(const RowMatrix3d& wi, const RowMatrix3d& wr)> exact;
  int exact_channels = 1;            // columns of exact(wi, wr)
  std::string exact_kind = "model";  // what `exact` is, for a column title: "model", "measured", "stored"
};

// A spectrum file (FILE.h5[#material]) as stored, InputError when it is missing; any other SOURCE, and a
// stored material with a half-angle lobe, fitted at `order` on the equal-area grid of `level`. A source
// with values everywhere (no delta part, not values at scattered samples only) also gets `exact`; with
// `values_only` such a source is not fitted at all (no spectrum unless one is stored). With `fit_allowed` false
// nothing is fitted: a source without values everywhere comes back with neither (a caller that needs the values
// refuses it before any work).
PictureMaterial load_picture_material(const std::string& text, int order, int level, bool values_only = false, bool fit_allowed = true);

// The material names of BANK.h5 when `text` names a bank file (no '#') holding more than one material,
// InputError when that file is missing; empty for any other SOURCE.
std::vector<std::string> several_bank_materials(const std::string& text);
// Material `name` of BANK.h5 `bank`: its spectrum as stored, or for a material with a half-angle lobe its
// values as `exact` (no spectrum).
PictureMaterial stored_bank_material(const std::string& bank, const std::string& name);
// For pictures drawn from values (`plot sphere --shading model`): a material with a spectrum but no `exact` (a
// stored spectrum, a bank material of modes) gets the spectrum's values as `exact` (icobrdf/io/material_eval.hpp:
// f, a spectrum of g divided by cos(theta_i)); others are left as they are.
void add_stored_values(PictureMaterial& m);

}  // namespace icobrdf
