#pragma once
// One material as a representation fitter sees it (MaterialProblem) and what a fitter returns
// (MaterialCandidate). The fitters (icobrdf/pipeline/modes_representation.hpp, half_angle_representation.hpp)
// include this header; the choice between them (icobrdf/pipeline/material_candidate.hpp) includes theirs.
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/scene.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/fit_source.hpp"
#include "icobrdf/pipeline/held_out.hpp"

namespace icobrdf {

struct MaterialCandidate;

// One (bytes, held-out error) a representation reached for a material: a candidate, or a step of a fitter's
// search (an order of the modes, a grid of a lobe). The bank keeps them (icobrdf/pipeline/bank_candidates.hpp)
// for the picture of error against bytes (`icobrdf plot bytes`).
struct CandidatePoint {
  std::string representation;  // "modes", "half-angle" or "hybrid"
  long long bytes = 0;
  double error_l2 = 0.0;       // relative L2 over the held-out pairs, in the material's metric
};

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
  // Where a fitter that misses the target leaves its lowest-error candidate within the budget (target_met
  // false, `note` saying where its search stopped), for on_miss = "keep-best"; nullptr: not wanted.
  std::vector<MaterialCandidate>* best_efforts = nullptr;
  // Where the points a fitter reaches go (note_tried), named by `representation` (choose_representation sets
  // both); nullptr: not kept.
  std::vector<CandidatePoint>* tried = nullptr;
  std::string representation{};
  // Work cap of a lobe search over measured data, in node-terms (icobrdf/pipeline/half_angle_representation.cpp
  // kLobeSearchWork); < 0: that default.
  long long lobe_work_cap = -1;
};

// Keeps (bytes, error_l2) of the fitter being run in p.tried, when kept and the error is finite.
inline void note_tried(const MaterialProblem& p, long long bytes, double error_l2) {
  if (p.tried && error_l2 == error_l2 && error_l2 < 1e308) p.tried->push_back({p.representation, bytes, error_l2});
}

struct MaterialCandidate {
  std::string representation;  // "modes", "half-angle" or "hybrid"
  MaterialRecord record;       // as the bank stores it; the builder adds the LUT, figures and labels
  long long bytes = 0;         // what the kept data costs (the choice minimizes it)
  bool measured = true;        // false for delta BRDFs: the errors are NaN
  HeldOutError error;          // held-out errors of the record
  bool target_met = true;      // false: the best within the budget (on_miss = "keep-best"), above the target
  // What the bank build report shows of the choice.
  bool isotropic = false;
  int level = -1, order = -1;  // fitting level, expansion order
  double anisotropy = 0.0;     // anisotropic energy fraction of the fit
  int kept = 0, total = 0;     // coefficients kept / in the full vector
  std::string note;            // a missed target: where the search stopped and the figure that stopped it
  // A missed target whose lobe search visited every grid within the budget (no work cap ended it): its lowest
  // error, the isotropic half-angle lobe's floor at that size as measured; NaN otherwise.
  double lobe_floor = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace icobrdf
