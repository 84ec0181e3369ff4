#pragma once
// Representations of a material in a bank, and the choice between them.
//
// A representation fitter turns one material (its source, its held-out errors, the scene's settings) into a
// MaterialCandidate that meets the material's target, or throws UnsupportedError saying why it cannot. The
// builder asks the representations the scene allows (Scene::representations, in the order of
// representations()) and keeps the candidate with the fewest bytes (the first listed on a tie); when none
// meets the target, the first representation's error is the material's. The representations:
//   "modes"       Helmholtz modes (icobrdf/pipeline/modes_representation.hpp)
//   "half-angle"  a half-angle factorized lobe alone (icobrdf/pipeline/half_angle_representation.hpp)
//   "hybrid"      a few isotropic modes plus a half-angle lobe (same header)
// A fitter told the bytes of the best candidate so far (MaterialProblem::bytes_to_beat) may give up as soon
// as it cannot beat them (UnsupportedError): that keeps materials the modes store in a few bytes as fast as
// before.
//
// Adding a representation: its fit in core/, its record fields in io/ (MaterialRecord and the bank file),
// and here one fitter appended to representations() (material_candidate.cpp).
#include <functional>
#include <string>
#include <vector>

#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/scene.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/fit_source.hpp"
#include "icobrdf/pipeline/held_out.hpp"

namespace icobrdf {

struct MaterialCandidate;

// Everything a representation fitter may use for one material.
struct MaterialProblem {
  const Scene& scene;
  const SceneMaterial& material;
  const BrdfSource& source;
  const HeldOutErrors* errors;  // nullptr when the source has delta parts (no pointwise error)
  FitContexts& contexts;        // fitting grids and projection contexts shared across the build
  std::function<void(const std::string&)> say;  // one progress line (never empty)
  long long bytes_to_beat = -1;                 // bytes of the best candidate so far; -1 when none
  const std::vector<MaterialCandidate>* earlier = nullptr;  // the candidates made before this fitter's
};

struct MaterialCandidate {
  std::string representation;  // "modes", "half-angle" or "hybrid"
  MaterialRecord record;       // as the bank stores it; the builder adds the LUT, figures and labels
  long long bytes = 0;         // what the kept data costs (the choice minimizes it)
  bool measured = true;        // false for delta BRDFs: the errors are NaN
  HeldOutError error;          // held-out errors of the record
  // What the bank build report shows of the choice.
  bool isotropic = false;
  int level = -1, order = -1;  // fitting level, expansion order
  double anisotropy = 0.0;     // anisotropic energy fraction of the fit
  int kept = 0, total = 0;     // coefficients kept / in the full vector
};

struct Representation {
  std::string name;
  std::function<MaterialCandidate(const MaterialProblem&)> fit;
};

const std::vector<Representation>& representations();

// The candidate with the fewest bytes over representations(); rethrows the first representation's
// UnsupportedError when none meets the target. Other errors propagate at once.
MaterialCandidate choose_representation(const MaterialProblem& problem);

}  // namespace icobrdf
