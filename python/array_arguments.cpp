#include "python/array_arguments.hpp"

namespace icobrdf::python {

RowMatrix3d directions(const DirArray& a, const char* what) {
  if (a.cols() != 3) throw ArgumentError(std::string(what) + ": expected an (n, 3) array of unit vectors, found (" +
                                         std::to_string(a.rows()) + ", " + std::to_string(a.cols()) + ")");
  return a;
}

Eigen::Vector3d incident_direction(const Eigen::Ref<const Eigen::VectorXd>& wi) {
  if (wi.size() != 3) throw ArgumentError("wi: expected a unit vector of 3 values, found " + std::to_string(wi.size()) + " values");
  return wi;
}

}  // namespace icobrdf::python
