#include "icobrdf/pipeline/material_candidate.hpp"

#include <algorithm>
#include <exception>
#include <optional>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/pipeline/half_angle_representation.hpp"
#include "icobrdf/pipeline/modes_representation.hpp"

namespace icobrdf {

const std::vector<Representation>& representations() {
  static const std::vector<Representation> all{
      {"modes", fit_modes_candidate}, {"half-angle", fit_half_angle_candidate}, {"hybrid", fit_hybrid_candidate}};
  return all;
}

MaterialCandidate choose_representation(const MaterialProblem& problem) {
  std::optional<MaterialCandidate> best;
  std::exception_ptr first_failure;
  std::string others;  // the other representations' reasons, appended to the first one's
  const auto& allowed = problem.scene.representations;
  std::vector<MaterialCandidate> made;
  for (const auto& r : representations()) {
    if (std::find(allowed.begin(), allowed.end(), r.name) == allowed.end()) continue;
    try {
      MaterialProblem p = problem;
      p.bytes_to_beat = best ? best->bytes : -1;
      p.earlier = &made;
      MaterialCandidate c = r.fit(p);
      if (!best || c.bytes < best->bytes) best = c;
      made.push_back(std::move(c));
    } catch (const UnsupportedError& e) {
      if (!first_failure) first_failure = std::current_exception();
      else others += std::string("; ") + e.what();
    }
  }
  if (!best && others.empty()) std::rethrow_exception(first_failure);
  if (!best) {
    try {
      std::rethrow_exception(first_failure);
    } catch (const UnsupportedError& e) {
      throw UnsupportedError(e.what() + others);
    }
  }
  return std::move(*best);
}

}  // namespace icobrdf
