#include "icobrdf/io/rgl_export.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/tables/bilinear_slices.hpp"
#include "icobrdf/core/tables/marginal_warp.hpp"
#include "icobrdf/io/tensor_file.hpp"

namespace icobrdf {
// Helpers in a namespace of their own: the library compiles in unity batches.
namespace rgl_export_detail {
namespace {

constexpr double kPi = 3.14159265358979323846;

double to_f32(double v) { return static_cast<double>(static_cast<float>(v)); }
double u_to_theta(double u) { return 0.5 * kPi * u * u; }
double theta_to_u(double theta) { return std::sqrt(theta * (2.0 / kPi)); }
Eigen::Vector3d direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}
// The incident direction a slice's tables are computed at: its node, or kRglGrazingSliceOffset inside the
// horizon for the node at pi/2.
Eigen::Vector3d slice_direction(double theta) { return direction(std::min(theta, 0.5 * kPi - kRglGrazingSliceOffset), 0.0); }
// Luminance of a row of 1 or 3 channels (Rec. 709 weights), negative values counting as 0.
double luminance(const Eigen::MatrixXd& v, Eigen::Index row) {
  if (v.cols() == 1) return std::max(0.0, v(row, 0));
  return 0.2126 * std::max(0.0, v(row, 0)) + 0.7152 * std::max(0.0, v(row, 1)) + 0.0722 * std::max(0.0, v(row, 2));
}
// The integral over phi in [0, 2 pi) of max(0, a cos phi + b), a >= 0.
double azimuth_integral(double a, double b) {
  if (b >= a) return 2 * kPi * b;
  if (b <= -a) return 0.0;
  const double p = std::acos(-b / a);
  return 2 * (a * std::sin(p) + b * p);
}
std::string vector_text(const Eigen::Vector3d& v) {
  return "(" + std::to_string(v.x()) + ", " + std::to_string(v.y()) + ", " + std::to_string(v.z()) + ")";
}
void check_finite(const Eigen::MatrixXd& f, const RowMatrix3d& wi, const RowMatrix3d& wo, const BrdfModel& model, const std::string& where) {
  for (Eigen::Index r = 0; r < f.rows(); ++r)
    for (Eigen::Index c = 0; c < f.cols(); ++c)
      if (!std::isfinite(f(r, c)))
        throw InputError(model.spec() + ": f is " + std::to_string(f(r, c)) + " at w_i = " + vector_text(wi.row(r).transpose()) +
                         ", w_o = " + vector_text(wo.row(r).transpose()) + " (" + where + " of the RGL export); expected a finite value");
}

// A 2 x N table over (u_theta, u_phi) of an isotropic function of u_theta: both rows the same.
BilinearSlices isotropic_table(const std::vector<double>& row) {
  std::vector<double> v(row);
  v.insert(v.end(), row.begin(), row.end());
  return BilinearSlices(v, static_cast<int>(row.size()), 2, ParameterGrid());
}

struct MicrofacetTables {
  std::vector<double> ndf, sigma;  // N values each (float32-rounded)
  BilinearSlices ndf_table, sigma_table;
};

// D from back-scattering, normalized to projected area 1, and sigma by quadrature of D's interpolant.
MicrofacetTables microfacet_tables(const BrdfModel& model, int n) {
  RowMatrix3d w(n, 3);
  for (int k = 0; k < n; ++k) w.row(k) = direction(u_to_theta(k / (n - 1.0)), 0.0).transpose();
  Eigen::MatrixXd back(n, model.channels());
  model.eval(w, w, back);
  check_finite(back, w, w, model, "back-scattering f(w, w), the ndf");
  std::vector<double> d(static_cast<size_t>(n));
  double peak = 0;
  for (int k = 0; k < n; ++k) {
    const double c = w(k, 2);
    d[static_cast<size_t>(k)] = luminance(back, k) * c * c;
    peak = std::max(peak, d[static_cast<size_t>(k)]);
  }
  if (!(peak > 0)) {  // no back-scattering at all: any positive D is valid, take cos^2 theta
    for (int k = 0; k < n; ++k) d[static_cast<size_t>(k)] = w(k, 2) * w(k, 2);
    peak = 1.0;
  }
  for (double& x : d) x = std::max(x, kRglNdfFloor * peak);
  // Midpoint nodes in u over [0, 1]: kRglSigmaSubdivisions per ndf interval; dw = sin theta pi u du dphi.
  const int q = (n - 1) * kRglSigmaSubdivisions;
  const auto quadrature = [&](const std::vector<double>& table, double theta_i) {
    const double si = std::sin(theta_i), ci = std::cos(theta_i);
    double acc = 0;
    for (int p = 0; p < q; ++p) {
      const double u = (p + 0.5) / q, th = u_to_theta(u);
      const PatchCoordinate pc = patch_coordinate(u, n);
      const double dm = interpolate(table[static_cast<size_t>(pc.index)], table[static_cast<size_t>(pc.index + 1)], pc.fraction);
      acc += dm * azimuth_integral(si * std::sin(th), ci * std::cos(th)) * std::sin(th) * kPi * u;
    }
    return acc / q;
  };
  const double area = quadrature(d, 0.0);  // integral of D cos theta dw
  MicrofacetTables t;
  for (double x : d) t.ndf.push_back(to_f32(x / area));
  for (int k = 0; k < n; ++k) t.sigma.push_back(to_f32(quadrature(t.ndf, u_to_theta(k / (n - 1.0)))));
  t.ndf_table = isotropic_table(t.ndf);
  t.sigma_table = isotropic_table(t.sigma);
  return t;
}

// The warp's point of a sample s (the inverse of MarginalWarp2D::invert) by bisection: invert's y depends on
// y alone and is non-decreasing, and its x is non-decreasing in x at a fixed y. warp_y solves for the y of a
// sample's y, warp_x for the x at that y.
double warp_y(const MarginalWarp2D& warp, const SliceBlend& blend, double sy) {
  double lo = 0, hi = 1;
  for (int it = 0; it < kRglWarpBisections; ++it) {
    const double mid = 0.5 * (lo + hi);
    (warp.invert(0.0, mid, blend).y() < sy ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}
double warp_x(const MarginalWarp2D& warp, const SliceBlend& blend, double y, double sx) {
  double lo = 0, hi = 1;
  for (int it = 0; it < kRglWarpBisections; ++it) {
    const double mid = 0.5 * (lo + hi);
    (warp.invert(mid, y, blend).x() < sx ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The warp's points of the r x r sample nodes of slice t (row-major, x along the row).
std::vector<Eigen::Vector2d> warped_nodes(const MarginalWarp2D& warp, int t, int r) {
  SliceBlend blend;
  blend.count = 1;
  blend.slice[0] = t;
  blend.weight[0] = 1.0;
  std::vector<Eigen::Vector2d> points(static_cast<size_t>(r) * r);
#pragma omp parallel for schedule(dynamic)
  for (int j = 0; j < r; ++j) {
    const double y = warp_y(warp, blend, j / (r - 1.0));
    for (int k = 0; k < r; ++k) points[static_cast<size_t>(j * r + k)] = {warp_x(warp, blend, y, k / (r - 1.0)), y};
  }
  return points;
}

void check_options(const RglExportOptions& o) {
  const auto at_least_2 = [](int v, const char* what) {
    if (v < 2 || v > 4096) throw ArgumentError(std::string("RGL export: ") + what + " must be 2 .. 4096, found " + std::to_string(v));
  };
  at_least_2(o.theta_nodes, "the number of incident elevations");
  at_least_2(o.value_resolution, "the value table resolution");
  at_least_2(o.vndf_resolution, "the vndf table resolution");
  at_least_2(o.ndf_resolution, "the ndf table resolution");
}

}  // namespace

RglExportSummary write_export(const std::string& path, const BrdfModel& model, const RglExportOptions& o) {
  check_options(o);
  const int nc = model.channels();
  if (nc != 1 && nc != 3)
    throw ArgumentError("RGL export of " + model.spec() + ": the RGB file needs 1 or 3 channels, the source has " + std::to_string(nc));
  const int nt = o.theta_nodes, r = o.value_resolution, v = o.vndf_resolution, n = o.ndf_resolution;
  const MicrofacetTables mt = microfacet_tables(model, n);
  std::vector<double> theta;
  for (int t = 0; t < nt; ++t) theta.push_back(to_f32(std::acos(1.0 - t / (nt - 1.0))));

  // vndf slices: D(m) max(0, w_i . m) u sin theta_m over (u_theta along x, relative u_phi along y).
  std::vector<double> vndf;
  vndf.reserve(static_cast<size_t>(nt) * v * v);
  for (int t = 0; t < nt; ++t) {
    const Eigen::Vector3d wi = slice_direction(theta[static_cast<size_t>(t)]);
    for (int j = 0; j < v; ++j)
      for (int k = 0; k < v; ++k) {
        const double ux = k / (v - 1.0), th = u_to_theta(ux);
        const Eigen::Vector3d m = direction(th, 2 * kPi * (j / (v - 1.0)) - kPi);
        vndf.push_back(to_f32(mt.ndf_table.eval(ux, 0.0, nullptr) * std::max(0.0, wi.dot(m)) * ux * std::sin(th)));
      }
  }
  const MarginalWarp2D warp(vndf, v, v, ParameterGrid({{0.0}, theta}));

  // Values: f cos theta_o 4 sigma / D at the warped nodes, slice by slice; luminance from them.
  RglExportSummary s{nt, r, v, n, 0, 0};
  const size_t per_slice = static_cast<size_t>(r) * r;
  std::vector<double> rgb(static_cast<size_t>(nt) * 3 * per_slice, 0.0), lum(static_cast<size_t>(nt) * per_slice, 0.0);
  for (int t = 0; t < nt; ++t) {
    const Eigen::Vector3d wi = slice_direction(theta[static_cast<size_t>(t)]);
    const double four_sigma = 4.0 * mt.sigma_table.eval(theta_to_u(theta[static_cast<size_t>(t)]), 0.5, nullptr);
    const std::vector<Eigen::Vector2d> points = warped_nodes(warp, t, r);
    std::vector<Eigen::Index> node;
    std::vector<double> scale;  // cos theta_o 4 sigma / D per valid node
    RowMatrix3d wis(static_cast<Eigen::Index>(per_slice), 3), wos(static_cast<Eigen::Index>(per_slice), 3);
    for (int j = 0; j < r; ++j)
      for (int k = 0; k < r; ++k) {
        const Eigen::Vector2d& u = points[static_cast<size_t>(j * r + k)];
        const Eigen::Vector3d m = direction(u_to_theta(u.x()), 2 * kPi * u.y() - kPi);
        const Eigen::Vector3d wo = (2.0 * wi.dot(m) * m - wi).normalized();
        if (!(wo.z() > 0)) {
          ++s.nodes_below_horizon;
          continue;
        }
        const auto row = static_cast<Eigen::Index>(node.size());
        wis.row(row) = wi.transpose();
        wos.row(row) = wo.transpose();
        node.push_back(j * r + k);
        scale.push_back(wo.z() * four_sigma / mt.ndf_table.eval(u.x(), 0.0, nullptr));
      }
    const auto valid = static_cast<Eigen::Index>(node.size());
    if (valid == 0) continue;  // (cannot happen: the node s = (0, y) is the normal)
    const RowMatrix3d wi_valid = wis.topRows(valid), wo_valid = wos.topRows(valid);
    Eigen::MatrixXd f(valid, nc);
    model.eval(wi_valid, wo_valid, f);
    check_finite(f, wi_valid, wo_valid, model, "a value node");
    double total = 0;
    for (Eigen::Index q = 0; q < valid; ++q) {
      const size_t at = static_cast<size_t>(node[static_cast<size_t>(q)]);
      for (int c = 0; c < 3; ++c)
        rgb[(static_cast<size_t>(t) * 3 + static_cast<size_t>(c)) * per_slice + at] = f(q, nc == 1 ? 0 : c) * scale[static_cast<size_t>(q)];
      const double y = luminance(f, q) * scale[static_cast<size_t>(q)];
      lum[static_cast<size_t>(t) * per_slice + at] = y;
      total += y;
    }
    if (!(total > 0)) std::fill(lum.begin() + static_cast<std::ptrdiff_t>(t * per_slice), lum.begin() + static_cast<std::ptrdiff_t>((t + 1) * per_slice), 1.0);
  }

  const auto un = static_cast<std::uint64_t>(n), unt = static_cast<std::uint64_t>(nt), ur = static_cast<std::uint64_t>(r), uv = static_cast<std::uint64_t>(v);
  std::vector<double> ndf2(mt.ndf), sigma2(mt.sigma);
  ndf2.insert(ndf2.end(), mt.ndf.begin(), mt.ndf.end());
  sigma2.insert(sigma2.end(), mt.sigma.begin(), mt.sigma.end());
  const std::string description = o.description.empty() ? "icobrdf export of " + model.spec() : o.description;
  write_tensor_file(path, {text_field("description", description), float32_field("phi_i", {1}, {0.0}), float32_field("theta_i", {unt}, theta),
                           float32_field("sigma", {2, un}, sigma2), float32_field("ndf", {2, un}, ndf2),
                           float32_field("vndf", {1, unt, uv, uv}, vndf), float32_field("luminance", {1, unt, ur, ur}, lum),
                           float32_field("rgb", {1, unt, 3, ur, ur}, rgb), uint8_field("jacobian", {1}, {1})});
  struct stat st{};
  if (::stat(path.c_str(), &st) == 0) s.bytes = st.st_size;
  return s;
}

}  // namespace rgl_export_detail

RglExportSummary write_rgl_export(const std::string& path, const BrdfModel& model, const RglExportOptions& options) {
  return rgl_export_detail::write_export(path, model, options);
}

}  // namespace icobrdf
