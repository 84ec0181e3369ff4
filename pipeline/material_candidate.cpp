#include "pipeline/material_candidate.hpp"

#include <exception>
#include <optional>

#include "core/error.hpp"
#include "pipeline/modes_representation.hpp"

namespace icobrdf {

const std::vector<Representation>& representations() {
  static const std::vector<Representation> all{{"modes", fit_modes_candidate}};
  return all;
}

MaterialCandidate choose_representation(const MaterialProblem& problem) {
  std::optional<MaterialCandidate> best;
  std::exception_ptr first_failure;
  for (const auto& r : representations()) {
    try {
      MaterialCandidate c = r.fit(problem);
      if (!best || c.bytes < best->bytes) best = std::move(c);
    } catch (const UnsupportedError&) {
      if (!first_failure) first_failure = std::current_exception();
    }
  }
  if (!best) std::rethrow_exception(first_failure);
  return std::move(*best);
}

}  // namespace icobrdf
