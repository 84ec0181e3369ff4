#include "icobrdf/io/material_eval.hpp"

#include "icobrdf/core/spectrum/spectrum_ops.hpp"

namespace icobrdf {

Eigen::MatrixXd add_lobe(const Eigen::MatrixXd& modes_values, const HalfAngleFactors& lobe, const RowMatrix3d& wi,
                         const RowMatrix3d& wr) {
  return (modes_values + lobe.eval(wi, wr)).cwiseMax(0.0);
}

Eigen::MatrixXd evaluate_material(const Spectrum& s, const std::optional<HalfAngleFactors>& lobe, const RowMatrix3d& wi,
                                  const RowMatrix3d& wr) {
  Eigen::MatrixXd out(wi.rows(), s.channel_count());
  for (int c = 0; c < s.channel_count(); ++c) {
    out.col(c) = evaluate_coefficients(s.channels[c], s.order, wi, wr);
    if (s.cosine) out.col(c) = out.col(c).cwiseQuotient(wi.col(2));
  }
  return lobe ? add_lobe(out, *lobe, wi, wr) : out;
}

}  // namespace icobrdf
