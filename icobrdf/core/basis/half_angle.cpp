#include "icobrdf/core/basis/half_angle.hpp"

#include <string>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

namespace {
void check_rows(Eigen::Index a, Eigen::Index b, const char* what) {
  if (a != b)
    throw ArgumentError(std::string(what) + ": the two direction matrices have " + std::to_string(a) + " and " +
                        std::to_string(b) + " rows; expected the same count");
}
}  // namespace

void half_diff_from_pairs(const RowMatrix3d& wi, const RowMatrix3d& wr, RowMatrix3d& h, RowMatrix3d& d) {
  check_rows(wi.rows(), wr.rows(), "half_diff_from_pairs");
  h.resize(wi.rows(), 3);
  d.resize(wi.rows(), 3);
  for (Eigen::Index k = 0; k < wi.rows(); ++k) {
    Eigen::Vector3d hk, dk;
    half_diff_from_pair(wi.row(k).transpose(), wr.row(k).transpose(), hk, dk);
    h.row(k) = hk.transpose();
    d.row(k) = dk.transpose();
  }
}

void pairs_from_half_diff(const RowMatrix3d& h, const RowMatrix3d& d, RowMatrix3d& wi, RowMatrix3d& wr) {
  check_rows(h.rows(), d.rows(), "pairs_from_half_diff");
  wi.resize(h.rows(), 3);
  wr.resize(h.rows(), 3);
  for (Eigen::Index k = 0; k < h.rows(); ++k) {
    Eigen::Vector3d a, b;
    pair_from_half_diff(h.row(k).transpose(), d.row(k).transpose(), a, b);
    wi.row(k) = a.transpose();
    wr.row(k) = b.transpose();
  }
}

HalfAngleMatrix half_angles_from_pairs(const RowMatrix3d& wi, const RowMatrix3d& wr) {
  check_rows(wi.rows(), wr.rows(), "half_angles_from_pairs");
  HalfAngleMatrix out(wi.rows(), 4);
  for (Eigen::Index k = 0; k < wi.rows(); ++k) {
    const HalfAngleCoords a = half_angle_from_pair(wi.row(k).transpose(), wr.row(k).transpose());
    out.row(k) << a.theta_h, a.phi_h, a.theta_d, a.phi_d;
  }
  return out;
}

void pairs_from_half_angles(const HalfAngleMatrix& angles, RowMatrix3d& wi, RowMatrix3d& wr) {
  wi.resize(angles.rows(), 3);
  wr.resize(angles.rows(), 3);
  for (Eigen::Index k = 0; k < angles.rows(); ++k) {
    Eigen::Vector3d a, b;
    pair_from_half_angle({angles(k, 0), angles(k, 1), angles(k, 2), angles(k, 3)}, a, b);
    wi.row(k) = a.transpose();
    wr.row(k) = b.transpose();
  }
}

}  // namespace icobrdf
