#pragma once
// BrdfModel: an analytic BRDF evaluated at batches of direction pairs, plus optional delta parts.
//
// Conventions (SPEC-NOTES): unit vectors, surface normal +z, incident w_i and remitted w_r both pointing
// away from the surface (Nicodemus). f is in 1/sr. Inputs are expected to be unit vectors (not re-normalized).
//
// Horizon: a direction with z < -kHorizonSlack is below the horizon and f = 0 there. A z in
// [-kHorizonSlack, 0] (rounding of points on the equator) is treated as z = 0, i.e. as grazing, and
// gets the grazing value of f (its limit), so cell averages over half cells on the equator are unbiased.
// Grazing (z = 0) and normal incidence give finite values for every model. Where f itself diverges
// (Minnaert k < 1 at grazing; Lommel-Seeliger, Hapke, height-correlated Smith microfacets and the
// qualitative Oren-Nayar at double grazing) the diverging cosine factor is floored at kGrazingCosFloor,
// i.e. f returns the value it has at cos theta = kGrazingCosFloor (theta = 89.99994 deg). docs/models.md
// lists the affected factors per model.
//
// Delta parts: g = f cos(theta_i) of a delta part is weight * delta(w_r, image of w_i), the delta being
// the one of the solid-angle measure on the hemisphere; image = (-x, -y, z) for the mirror and w_i itself
// for the retroreflector. Weight 1 conserves radiance (K&vD 1998, eqs. 27 and 31). eval() returns the
// regular (non-delta) part only.
//
// Thread safety: models are immutable after construction; eval() may be called from many threads.
#include <Eigen/Core>

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "icobrdf/core/grid/grid.hpp"
#include "icobrdf/core/basis/horizon.hpp"

namespace icobrdf {

// Floor of the cosines in factors that diverge at grazing (documented per model).
inline constexpr double kGrazingCosFloor = 1e-6;

struct DeltaPart {
  enum Kind { Mirror, Retroreflector } kind;
  double weight;
};

class BrdfModel {
 public:
  virtual ~BrdfModel() = default;
  virtual int channels() const { return 1; }
  // Regular (non-delta) part of f at many pairs: wi, wr are rows x 3; out is rows x channels().
  // Throws ArgumentError on mismatched shapes.
  virtual void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const = 0;
  // The regular part at one incident direction against many (a row of a LUT): out row k is f(wi, wr row k),
  // rows x channels(), bitwise equal to eval with wi repeated in every row, which is what this default
  // does. A model may override it to take the incident side once (MicrofacetModel, SumModel).
  virtual void eval_row(const Eigen::Vector3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const;
  // Channel 0 of the regular part at one pair (convenience; slow for many pairs).
  double eval(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const;
  virtual std::vector<DeltaPart> delta_parts() const { return {}; }
  virtual bool is_isotropic() const { return true; }
  virtual bool is_reciprocal() const { return true; }
  // Canonical SOURCE string (without the "model:" prefix); parse_model(spec()) gives the same model.
  virtual std::string spec() const = 0;
};

// A model whose value depends on one channel only, evaluated pair by pair: derived classes implement
// value() for two directions already known to be on or above the horizon (z >= 0).
class ScalarBrdfModel : public BrdfModel {
 public:
  using BrdfModel::eval;
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override;
  // f at one pair; both z >= 0 (the caller clamps the horizon slack to 0).
  virtual double value(const Eigen::Vector3d& wi, const Eigen::Vector3d& wr) const = 0;
};

// Ideal mirror (eq. 27) and ideal retroreflector (eq. 31): delta part of weight 1, regular part 0.
class MirrorModel final : public BrdfModel {
 public:
  using BrdfModel::eval;
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override;
  std::vector<DeltaPart> delta_parts() const override { return {{DeltaPart::Mirror, 1.0}}; }
  std::string spec() const override { return "mirror"; }
};
class RetroreflectorModel final : public BrdfModel {
 public:
  using BrdfModel::eval;
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override;
  std::vector<DeltaPart> delta_parts() const override { return {{DeltaPart::Retroreflector, 1.0}}; }
  std::string spec() const override { return "retroreflector"; }
};

// Weighted sum sum_k w_k f_k (a single term is a scaling). Weights are finite and >= 0. Sums given as
// terms are flattened (their terms join this one with multiplied weights). Channels: a 1-channel term
// is broadcast to every channel; terms with more channels must all have the same count (else
// ArgumentError). Delta parts are summed per kind with the weights applied.
class SumModel final : public BrdfModel {
 public:
  struct Term {
    double weight;
    std::shared_ptr<const BrdfModel> model;
  };
  explicit SumModel(std::vector<Term> terms);
  using BrdfModel::eval;
  int channels() const override { return channels_; }
  void eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override;
  void eval_row(const Eigen::Vector3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const override;
  std::vector<DeltaPart> delta_parts() const override;
  bool is_isotropic() const override;
  bool is_reciprocal() const override;
  // "w1*spec1+w2*spec2"; a weight of exactly 1 is omitted.
  std::string spec() const override;
  const std::vector<Term>& terms() const { return terms_; }

 private:
  std::vector<Term> terms_;
  int channels_ = 1;
};

// Shortest decimal string that reads back (strtod) to exactly x: "0.2", "1e-05", "3".
std::string format_parameter(double x);
// "name" or "name:key=value,key=value" from already formatted values (order kept).
std::string format_model_spec(const std::string& name, const std::vector<std::pair<std::string, std::string>>& params);

// Checks that wi, wr and out have matching rows and out has `channels` columns; ArgumentError otherwise.
void check_pair_shapes(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::Ref<Eigen::MatrixXd>& out,
                       int channels);

}  // namespace icobrdf
