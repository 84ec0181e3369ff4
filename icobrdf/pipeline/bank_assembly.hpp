#pragma once
// The bank's own grid and operators, and the records as the bank stores them.
//
// The bank stores its grid (level `level`) with B and G for every order used, and P where that grid supports
// the order (its Gram error is within the default tolerance); reconstruction F = B C B^T needs only B.
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "icobrdf/core/projection/discrete_basis.hpp"
#include "icobrdf/core/projection/projection.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/scene.hpp"
#include "icobrdf/pipeline/material_candidate.hpp"

namespace icobrdf {

// Safe to call from several threads at once (a bank build fits several materials at once): one lock guards
// the grid and the operators while they are built; what they return stays valid and is not changed after.
class BankOperators {
 public:
  explicit BankOperators(const Scene& scene) : scene_(scene) {}
  // The stored /grid with its full cubature.
  const Grid& grid();
  // Adds B, G, P (when supported), the filter weights and the (n, l) index table of `order` under /basis.
  void add_basis(BankContents& bank, int order);
  // The record of a chosen candidate with its LUT on the bank grid when the scene stores LUTs.
  MaterialRecord finish_record(MaterialCandidate candidate);

 private:
  struct Operators {
    DiscreteBasis basis;
    std::optional<ProjectionOperator> projection;
  };
  const Operators& operators(int order);
  const Grid& grid_locked();

  const Scene& scene_;
  std::mutex lock_;
  std::shared_ptr<const Grid> grid_;
  std::map<int, std::unique_ptr<Operators>> operators_;
};

// What a bank stores besides its materials (which icobrdf/io/bank_file.hpp BankWriter writes as they finish):
// the grid and the operators of every order in `orders` (the materials' orders, repeats allowed).
BankContents bank_operators_part(BankOperators& operators, std::vector<int> orders);

}  // namespace icobrdf
