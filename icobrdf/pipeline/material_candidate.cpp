#include "icobrdf/pipeline/material_candidate.hpp"

#include <algorithm>
#include <cstdio>
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
  const long long budget = problem.material.max_bytes;
  std::vector<MaterialCandidate> made, best_efforts;
  for (const auto& r : representations()) {
    if (std::find(allowed.begin(), allowed.end(), r.name) == allowed.end()) continue;
    try {
      MaterialProblem p = problem;
      p.bytes_to_beat = best ? best->bytes : budget >= 0 ? budget + 1 : -1;
      p.earlier = &made;
      p.best_efforts = &best_efforts;
      p.representation = r.name;
      MaterialCandidate c = r.fit(p);
      note_tried(p, c.bytes, c.error.l2);
      if (budget >= 0 && c.bytes > budget)
        throw UnsupportedError(r.name + ": " + std::to_string(c.bytes) + " bytes meet the target, above max_bytes " + std::to_string(budget));
      if (!best || c.bytes < best->bytes) best = c;
      made.push_back(std::move(c));
    } catch (const UnsupportedError& e) {
      if (!first_failure) first_failure = std::current_exception();
      else others += std::string("; ") + e.what();
    }
  }
  if (best) return std::move(*best);
  std::string why = others;
  if (first_failure) {
    try {
      std::rethrow_exception(first_failure);
    } catch (const UnsupportedError& e) {
      why = e.what() + others;
    }
  }
  // No candidate meets the target within the budget: the lowest error within it, kept or named: the fitters'
  // best efforts (a lobe search that stopped short), and the modes when the scene allows them or nothing else
  // is left.
  if (budget >= 0 || problem.material.on_miss == OnMiss::KeepBest) {
    const bool modes_allowed = std::find(allowed.begin(), allowed.end(), "modes") != allowed.end();
    if (modes_allowed || best_efforts.empty()) {
      try {
        best_efforts.push_back(fit_modes_within_budget(problem));
        MaterialProblem p = problem;
        p.representation = "modes";
        note_tried(p, best_efforts.back().bytes, best_efforts.back().error.l2);
      } catch (const UnsupportedError& e) {
        if (best_efforts.empty()) throw UnsupportedError(why + "; " + e.what());
      }
    }
    MaterialCandidate c = std::move(*std::min_element(best_efforts.begin(), best_efforts.end(), [](const auto& a, const auto& b) {
      return a.error.l2 < b.error.l2 || (a.error.l2 == b.error.l2 && a.bytes < b.bytes);
    }));
    c.target_met = c.error.l2 <= problem.material.target;
    if (c.target_met || problem.material.on_miss == OnMiss::KeepBest) return c;
    char buf[200];
    std::snprintf(buf, sizeof buf, "; the lowest error within max_bytes %lld is %.3g (%s, %lld bytes; on_miss = \"keep-best\" would keep it)", budget,
                  c.error.l2, c.representation.c_str(), c.bytes);
    why += buf;
  }
  throw UnsupportedError(why);
}

}  // namespace icobrdf
