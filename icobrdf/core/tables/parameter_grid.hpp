#pragma once
// ParameterGrid: multilinear interpolation weights over a tensor of 2-D slices indexed by D parameters
// (D = 0..3), the scheme of the conditional 2-D tables of the RGL measured-BRDF format
// (icobrdf/io/rgl_bsdf.hpp; Dupuy & Jakob 2018).
//
// Axis d holds n_d >= 1 node values, strictly increasing. Slices are stored with the first axis slowest:
// slice index = sum_d i_d * stride_d, stride_{D-1} = 1, stride_d = n_{d+1} * stride_{d+1}.
// For a parameter value x on an axis with n_d >= 2 nodes v_0 < ... < v_{n-1}:
//   i = the largest node index with v_i < x, clamped to [0, n - 2] (0 when x <= v_0),
//   t = clamp((x - v_i) / (v_{i+1} - v_i), 0, 1),
// and the axis contributes the pair (i, 1 - t), (i + 1, t): outside the node range the end slice is held
// (no extrapolation). An axis with one node contributes that node with weight 1 whatever x is.
// A blend is the product of the axes' pairs: up to 2^D (slice, weight) corners whose weights sum to 1.
// A NaN parameter is treated like x <= v_0.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace icobrdf {

inline constexpr int kMaxGridParameters = 3;

struct SliceBlend {
  std::array<std::int64_t, 1 << kMaxGridParameters> slice{};
  std::array<double, 1 << kMaxGridParameters> weight{};
  int count = 0;
};

class ParameterGrid {
 public:
  ParameterGrid() = default;
  // ArgumentError for more than kMaxGridParameters axes, an empty axis, non-finite or non-increasing nodes.
  explicit ParameterGrid(std::vector<std::vector<double>> axes);
  int dimension() const { return static_cast<int>(axes_.size()); }
  std::int64_t slices() const { return slices_; }
  const std::vector<double>& axis(int d) const { return axes_[static_cast<size_t>(d)]; }
  // `params` has dimension() values.
  SliceBlend blend(const double* params) const;

 private:
  std::vector<std::vector<double>> axes_;
  std::vector<std::int64_t> strides_;
  std::int64_t slices_ = 1;
};

}  // namespace icobrdf
