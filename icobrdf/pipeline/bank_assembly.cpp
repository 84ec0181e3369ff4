#include "icobrdf/pipeline/bank_assembly.hpp"

#include <algorithm>

#include "icobrdf/core/models/function_model.hpp"
#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/core/basis/lowpass_filter.hpp"
#include "icobrdf/core/projection/lut.hpp"
#include "icobrdf/io/material_eval.hpp"
#include "icobrdf/mesh/tessellation.hpp"

namespace icobrdf {

const Grid& BankOperators::grid() {
  std::lock_guard<std::mutex> g(lock_);
  return grid_locked();
}

const Grid& BankOperators::grid_locked() {
  if (!grid_) grid_ = std::make_shared<const Grid>(build_equal_area_grid(scene_.level));
  return *grid_;
}

// B and G at any order; P only where the bank grid supports the order (icobrdf/core/projection/discrete_basis.hpp), else it is
// left out of the file.
const BankOperators::Operators& BankOperators::operators(int order) {
  std::lock_guard<std::mutex> g(lock_);
  auto& c = operators_[order];
  if (!c) {
    c = std::make_unique<Operators>();
    c->basis = build_discrete_basis(grid_locked(), order);
    if (c->basis.gram_error <= kDefaultGramTolerance) c->projection = make_projection(c->basis);
  }
  return *c;
}

void BankOperators::add_basis(BankContents& bank, int order) {
  const auto& ctx = operators(order);
  const std::string p = std::to_string(order);
  bank.basis.push_back(BasisArray::matrix(p + "/B", ctx.basis.B, "1/sqrt(sr)", "cells x modes: cell averages of K_j (ANSI order)"));
  bank.basis.push_back(BasisArray::matrix(p + "/G", ctx.basis.G, "1", "modes x modes: Gram matrix B^T W B"));
  if (ctx.projection)
    bank.basis.push_back(BasisArray::matrix(p + "/P", ctx.projection->P, "sr^(1/2)",
                                            "cells x modes: least-squares projection W B G^-1; C = P^T F P"));
  // Smoothing S = B diag(w) P^T is stored in this factored form (S itself is cells x cells); the bank's
  // spectra are plain truncations, so w = 1 (icobrdf/core/basis/lowpass_filter.hpp gives other filters' weights).
  const Eigen::VectorXd w = mode_weights(LowPassFilter{}, order);
  bank.basis.push_back(BasisArray::matrix(p + "/filter_weights", Eigen::MatrixXd(w.transpose()), "1",
                                          "1 x modes: low-pass weights w of the smoothing S = B diag(w) P^T (plain truncation)"));
  BasisArray idx;
  idx.path = p + "/indices";
  const int m = hemisphere_basis_count(order);
  idx.shape = {static_cast<std::uint64_t>(m), 2};
  for (int j = 0; j < m; ++j) {
    idx.indices.push_back(ansi_to_nl(j).n);
    idx.indices.push_back(ansi_to_nl(j).l);
  }
  idx.unit = "index";
  idx.description = "modes x 2: (n, l) of K_j in ANSI order j = (n(n+2)+l)/2";
  bank.basis.push_back(std::move(idx));
}

MaterialRecord BankOperators::finish_record(MaterialCandidate candidate) {
  MaterialRecord rec = std::move(candidate.record);
  if (scene_.store_lut) {
    const auto& ctx = operators(rec.spectrum.order);
    if (!rec.lobe) {
      for (const auto& c : rec.spectrum.channels) rec.lut.push_back(reconstruct_lut(ctx.basis, c));
    } else {
      // The material's values (modes + lobe, icobrdf/io/material_eval.hpp) averaged over the cell pairs with the bank
      // grid's cubature (f form unless the spectrum is of g, whose LUT is then of g as well).
      const Spectrum& s = rec.spectrum;
      const std::optional<HalfAngleFactors>& lobe = rec.lobe;
      const FunctionModel model(
          s.channel_count(),
          [&s, &lobe](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
            out = evaluate_material(s, lobe, wi, wr);
          },
          "stored material", s.isotropic && lobe->isotropic, true);
      rec.lut = build_lut(model, grid(), s.cosine, LutSampling::CellAverage).channels;
    }
    // The LUT lives on the bank grid; the fitting level stays in the figure fit_level.
    rec.spectrum.level = scene_.level;
    rec.spectrum.grid_kind = to_string(GridKind::EqualArea);
    rec.lut_float32 = scene_.lut_float32;
  }
  return rec;
}

BankContents bank_operators_part(BankOperators& operators, std::vector<int> orders) {
  BankContents bank;
  bank.grid = operators.grid();
  std::sort(orders.begin(), orders.end());
  orders.erase(std::unique(orders.begin(), orders.end()), orders.end());
  for (int n : orders) operators.add_basis(bank, n);
  return bank;
}

}  // namespace icobrdf
