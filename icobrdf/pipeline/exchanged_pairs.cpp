#include "icobrdf/pipeline/exchanged_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace icobrdf {
namespace {

double polar(const RowMatrix3d& w, Eigen::Index k) { return std::atan2(std::hypot(w(k, 0), w(k, 1)), w(k, 2)); }

// |phi_i - phi_r| in [0, pi]; 0 when either direction is at the pole.
double azimuth_gap(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Index k) {
  const double g = std::abs(std::remainder(std::atan2(wi(k, 1), wi(k, 0)) - std::atan2(wr(k, 1), wr(k, 0)), 2 * M_PI));
  return std::hypot(wi(k, 0), wi(k, 1)) > 0 && std::hypot(wr(k, 0), wr(k, 1)) > 0 ? g : 0.0;
}

}  // namespace

std::vector<Eigen::Index> exchanged_partners(const RowMatrix3d& wi, const RowMatrix3d& wr, double tolerance_deg, bool about_normal) {
  const Eigen::Index n = wi.rows();
  const double cos_tol = std::cos(tolerance_deg * M_PI / 180);
  // Two unit vectors within angle t differ in z by at most t (radians): a partner's w_i.z is within t of w_r.z.
  const double dz = tolerance_deg * M_PI / 180;
  std::vector<Eigen::Index> by_z(static_cast<size_t>(n));
  std::iota(by_z.begin(), by_z.end(), Eigen::Index{0});
  std::sort(by_z.begin(), by_z.end(), [&](Eigen::Index a, Eigen::Index b) { return wi(a, 2) < wi(b, 2); });
  std::vector<double> z(static_cast<size_t>(n));
  for (Eigen::Index k = 0; k < n; ++k) z[static_cast<size_t>(k)] = wi(by_z[static_cast<size_t>(k)], 2);
  std::vector<Eigen::Index> partner(static_cast<size_t>(n), -1);
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto lo = std::lower_bound(z.begin(), z.end(), wr(k, 2) - dz), hi = std::upper_bound(z.begin(), z.end(), wr(k, 2) + dz);
    double best = -1e300;
    for (auto it = lo; it != hi; ++it) {
      const Eigen::Index l = by_z[static_cast<size_t>(it - z.begin())];
      if (l == k) continue;
      if (about_normal) {
        const double tol = tolerance_deg * M_PI / 180;
        const double d = std::max({std::abs(polar(wi, l) - polar(wr, k)), std::abs(polar(wr, l) - polar(wi, k)),
                                   std::abs(azimuth_gap(wi, wr, l) - azimuth_gap(wi, wr, k))});
        if (d > tol) continue;
        if (-d > best) best = -d, partner[static_cast<size_t>(k)] = l;
        continue;
      }
      const double a = wi.row(l).dot(wr.row(k)), b = wr.row(l).dot(wi.row(k));
      if (a < cos_tol || b < cos_tol) continue;
      if (a + b > best) best = a + b, partner[static_cast<size_t>(k)] = l;
    }
  }
  return partner;
}

ExchangedAsymmetry exchanged_asymmetry(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& f, bool cosine,
                                       double tolerance_deg, bool about_normal) {
  const std::vector<Eigen::Index> partner = exchanged_partners(wi, wr, tolerance_deg, about_normal);
  ExchangedAsymmetry out;
  double ref = 0.0, anti = 0.0;
  std::vector<double> rel;
  for (Eigen::Index k = 0; k < wi.rows(); ++k) {
    const Eigen::Index l = partner[static_cast<size_t>(k)];
    if (l < 0) continue;
    ++out.samples;
    const double w = cosine ? wi(k, 2) * wr(k, 2) : 1.0;
    ref += w * w * f.row(k).squaredNorm();
    anti += w * w * 0.25 * (f.row(k) - f.row(l)).squaredNorm();
    if (k < l)
      for (Eigen::Index c = 0; c < f.cols(); ++c) {
        const double mean = 0.5 * (std::abs(f(k, c)) + std::abs(f(l, c)));
        if (mean > 0) rel.push_back(std::abs(f(k, c) - f(l, c)) / mean);
      }
  }
  if (out.samples == 0) return out;
  out.asymmetry = ref > 0 ? std::sqrt(anti / ref) : 0.0;
  if (!rel.empty()) {
    const auto mid = rel.begin() + static_cast<std::ptrdiff_t>(rel.size() / 2);
    std::nth_element(rel.begin(), mid, rel.end());
    out.median_relative_difference = *mid;
    if (rel.size() % 2 == 0) out.median_relative_difference = 0.5 * (*mid + *std::max_element(rel.begin(), mid));
  }
  return out;
}

}  // namespace icobrdf
