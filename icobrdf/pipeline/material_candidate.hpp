#pragma once
// Representations of a material in a bank, and the choice between them.
//
// A representation fitter turns one material (its source, its held-out errors, the scene's settings) into a
// MaterialCandidate that meets the material's target, or throws UnsupportedError saying why it cannot. The
// builder asks the representations the scene allows (Scene::representations, in the order of
// representations()) and keeps the candidate with the fewest bytes (the first listed on a tie) within the
// material's max_bytes; when none meets the target within it, and the material has a budget or
// on_miss = "keep-best", the lowest error within the budget is the candidate (target_met false when above the
// target; on_miss = "fail" then fails naming that error): among the fitters' best efforts
// (MaterialProblem::best_efforts: the lobe of a measured material's search that stopped short) and the modes
// within the budget (fit_modes_within_budget; when the scene allows modes, or nothing else was left);
// otherwise the first representation's error is the material's. The representations:
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

#include "icobrdf/pipeline/material_problem.hpp"

namespace icobrdf {

struct Representation {
  std::string name;
  std::function<MaterialCandidate(const MaterialProblem&)> fit;
};

const std::vector<Representation>& representations();

// The candidate with the fewest bytes over representations() within max_bytes, or the best effort above;
// UnsupportedError (the first representation's reason first) when the material fails. Other errors
// propagate at once.
MaterialCandidate choose_representation(const MaterialProblem& problem);

}  // namespace icobrdf
