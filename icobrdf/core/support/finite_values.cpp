#include "icobrdf/core/support/finite_values.hpp"

#include <cmath>
#include <cstdio>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

std::string number_text(double x) {
  if (std::isnan(x)) return "NaN";
  return x > 0 ? "+Inf" : "-Inf";
}

[[noreturn]] void refuse(double value, const std::string& index, const std::string& where, const std::string& step) {
  throw UnsupportedError(where + ": " + step + " gave " + number_text(value) + " at " + index +
                         ", expected finite values (the result leaves the double range); nothing written");
}

}  // namespace

void require_finite(const Eigen::Ref<const Eigen::MatrixXd>& values, const std::string& where, const std::string& step) {
  for (Eigen::Index c = 0; c < values.cols(); ++c)
    for (Eigen::Index r = 0; r < values.rows(); ++r)
      if (!std::isfinite(values(r, c)))
        refuse(values(r, c), values.cols() == 1 ? "[" + std::to_string(r) + "]" : "[" + std::to_string(r) + ", " + std::to_string(c) + "]",
               where, step);
}

void require_finite(double value, const std::string& where, const std::string& step) {
  if (!std::isfinite(value)) refuse(value, "[0]", where, step);
}

}  // namespace icobrdf
