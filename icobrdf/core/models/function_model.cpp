#include "icobrdf/core/models/function_model.hpp"

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

void FunctionModel::eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const {
  if (wi.rows() != wr.rows() || out.rows() != wi.rows() || out.cols() != channels_)
    throw ArgumentError("FunctionModel::eval: expected " + std::to_string(wi.rows()) + " x " + std::to_string(channels_) +
                        " values for " + std::to_string(wi.rows()) + " pairs, found " + std::to_string(out.rows()) + " x " +
                        std::to_string(out.cols()) + " and " + std::to_string(wr.rows()) + " remitted directions");
  values_(wi, wr, out);
}

}  // namespace icobrdf
