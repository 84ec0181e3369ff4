#pragma once
// FunctionModel: a BrdfModel whose values come from a function of direction pairs: a stored representation
// (a bank material with a half-angle lobe), the residual a hybrid fit leaves, any SOURCE that is not an
// analytic model. It lets everything that samples models (LUTs, projections, fits) take such a function.
//
// The function receives batches of pairs (rows x 3 each, unit vectors) and fills out (rows x channels) with
// f [1/sr]; it must be safe to call from several threads. No delta parts. is_isotropic() and
// is_reciprocal() return what the constructor is told (they select faster paths in the projections: claim
// only what holds).
#include <functional>
#include <string>

#include "icobrdf/core/models/brdf_model.hpp"

namespace icobrdf {

class FunctionModel final : public BrdfModel {
 public:
  using Values = std::function<void(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out)>;
  FunctionModel(int channels, Values values, std::string spec, bool isotropic, bool reciprocal)
      : channels_(channels), values_(std::move(values)), spec_(std::move(spec)), isotropic_(isotropic), reciprocal_(reciprocal) {}

  using BrdfModel::eval;
  int channels() const override { return channels_; }
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override;
  bool is_isotropic() const override { return isotropic_; }
  bool is_reciprocal() const override { return reciprocal_; }
  std::string spec() const override { return spec_; }

 private:
  int channels_;
  Values values_;
  std::string spec_;
  bool isotropic_, reciprocal_;
};

}  // namespace icobrdf
