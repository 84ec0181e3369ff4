#include "python/array_arguments.hpp"

#include <cmath>

#include "icobrdf/io/unit_directions.hpp"

namespace icobrdf::python {

void require_finite_argument(const Eigen::Ref<const Eigen::MatrixXd>& a, const char* what) {
  if (a.allFinite()) return;
  for (Eigen::Index c = 0; c < a.cols(); ++c)
    for (Eigen::Index r = 0; r < a.rows(); ++r)
      if (!std::isfinite(a(r, c)))
        throw ArgumentError(std::string(what) + ": expected finite values, found " + std::to_string(a(r, c)) + " at row " +
                            std::to_string(r) + ", column " + std::to_string(c));
}

Eigen::Map<const RowMatrix3d> direction_rows(const DirArray& a, const char* what) {
  const bool one = a.ndim() == 1 && a.shape(0) == 3;
  if (!one && !(a.ndim() == 2 && a.shape(1) == 3)) {
    std::string shape;
    for (py::ssize_t k = 0; k < a.ndim(); ++k) shape += (k ? ", " : "") + std::to_string(a.shape(k));
    if (a.ndim() == 1) shape += ",";
    throw ArgumentError(std::string(what) + ": expected an (n, 3) array of unit vectors or one direction of shape (3,), found (" + shape + ")");
  }
  const Eigen::Index n = one ? 1 : static_cast<Eigen::Index>(a.shape(0));
  Eigen::Map<const RowMatrix3d> rows(a.data(), n, 3);
  require_unit_directions(rows, what, false);
  return rows;
}

RowMatrix3d directions(const DirArray& a, const char* what) { return direction_rows(a, what); }

Eigen::Vector3d incident_direction(const Eigen::Ref<const Eigen::VectorXd>& wi) {
  if (wi.size() != 3) throw ArgumentError("wi: expected a unit vector of 3 values, found " + std::to_string(wi.size()) + " values");
  return wi;
}

Eigen::Index pair_count(const DirArray& wi, const DirArray& wr) {
  const Eigen::Index a = wi.ndim() == 1 ? 1 : static_cast<Eigen::Index>(wi.shape(0));
  const Eigen::Index b = wr.ndim() == 1 ? 1 : static_cast<Eigen::Index>(wr.shape(0));
  if (a == b || wr.ndim() == 1) return a;
  if (wi.ndim() == 1) return b;
  throw ArgumentError("wi has " + std::to_string(a) + " rows, wr has " + std::to_string(b) +
                      ", expected the same number, or one direction of shape (3,) for one of them");
}

void pair_rows(const Eigen::Map<const RowMatrix3d>& w, Eigen::Index r0, Eigen::Index m, RowMatrix3d& out) {
  if (w.rows() == 1) out = w.row(0).replicate(m, 1);
  else out = w.middleRows(r0, m);
}

std::pair<RowMatrix3d, RowMatrix3d> direction_pairs(const DirArray& wi, const DirArray& wr) {
  const auto a = direction_rows(wi, "wi");
  const auto b = direction_rows(wr, "wr");
  const Eigen::Index n = pair_count(wi, wr);
  std::pair<RowMatrix3d, RowMatrix3d> out;
  pair_rows(a, 0, n, out.first);
  pair_rows(b, 0, n, out.second);
  return out;
}

}  // namespace icobrdf::python
