#include "icobrdf/io/rgl_bsdf.hpp"

#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/tables/grid_noise.hpp"
#include "icobrdf/io/tensor_file.hpp"

namespace icobrdf {

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Reader {
  const TensorFile& tf;
  [[noreturn]] void fail(const std::string& field, const std::string& what) const {
    throw InputError(tf.path + ": RGL material field '" + field + "': " + what);
  }
  const TensorField& field(const std::string& name, TensorDtype dtype, size_t ndim) const {
    const TensorField* f = tf.find(name);
    if (!f) throw InputError(tf.path + ": RGL material: missing field '" + name + "' (expected " + to_string(dtype) + ", " + std::to_string(ndim) + "-D)");
    if (f->dtype != dtype) fail(name, "expected " + to_string(dtype) + ", found " + to_string(f->dtype));
    if (f->shape.size() != ndim)
      fail(name, "expected " + std::to_string(ndim) + " dimensions, found shape " + f->shape_text());
    return *f;
  }
  // Values checked finite (and >= 0 when `nonnegative`).
  std::vector<double> finite_values(const TensorField& f, bool nonnegative) const {
    std::vector<double> v = f.values();
    for (size_t k = 0; k < v.size(); ++k)
      if (!std::isfinite(v[k]) || (nonnegative && v[k] < 0))
        fail(f.name, "value " + std::to_string(k) + ": expected a finite number" + (nonnegative ? " >= 0" : "") + ", found " + std::to_string(v[k]));
    return v;
  }
  std::vector<double> increasing_axis(const TensorField& f) const {
    std::vector<double> v = finite_values(f, false);
    if (v.empty()) fail(f.name, "expected at least one node, found none");
    for (size_t k = 1; k < v.size(); ++k)
      if (!(v[k] > v[k - 1])) fail(f.name, "expected strictly increasing nodes, node " + std::to_string(k) + " is " + std::to_string(v[k]) + " after " + std::to_string(v[k - 1]));
    return v;
  }
  void require_dim(const TensorField& f, size_t d, std::uint64_t expected, const std::string& why) const {
    if (f.shape[d] != expected)
      fail(f.name, "shape " + f.shape_text() + ": dimension " + std::to_string(d) + " expected " + std::to_string(expected) + " (" + why + "), found " + std::to_string(f.shape[d]));
  }
  void require_table(const TensorField& f, size_t d) const {  // dims d, d+1 are a 2-D table of >= 2 x 2 nodes
    if (f.shape[d] < 2 || f.shape[d + 1] < 2 || f.shape[d] > (1u << 20) || f.shape[d + 1] > (1u << 20))
      fail(f.name, "shape " + f.shape_text() + ": expected a table of 2 .. 1048576 nodes per side in the last two dimensions");
  }
};

double elevation(double x, double y, double z) { return 2.0 * std::asin(std::min(1.0, 0.5 * std::sqrt(x * x + y * y + (z - 1) * (z - 1)))); }
double theta_to_u(double theta) { return std::sqrt(theta * (2.0 / kPi)); }
double phi_to_u(double phi) { return (phi + kPi) * (0.5 / kPi); }

}  // namespace

RglBsdf read_rgl_bsdf(const std::string& path) {
  const TensorFile tf = read_tensor_file(path);
  const Reader r{tf};
  RglBsdf b;
  b.path = path;
  const TensorField& desc = r.field("description", TensorDtype::UInt8, 1);
  b.description.assign(desc.bytes.begin(), desc.bytes.end());
  b.theta_i = r.increasing_axis(r.field("theta_i", TensorDtype::Float32, 1));
  b.phi_i = r.increasing_axis(r.field("phi_i", TensorDtype::Float32, 1));
  const std::uint64_t np = b.phi_i.size(), nt = b.theta_i.size();
  b.spectral = tf.find("wavelengths") != nullptr;
  const std::string values_name = b.spectral ? "spectra" : "rgb";
  if (b.spectral) b.wavelengths = r.increasing_axis(r.field("wavelengths", TensorDtype::Float32, 1));
  const std::vector<double> lambda_axis = b.spectral ? b.wavelengths : std::vector<double>{0, 1, 2};

  const TensorField& jac = r.field("jacobian", TensorDtype::UInt8, 1);
  r.require_dim(jac, 0, 1, "one flag");
  if (jac.bytes[0] > 1) r.fail("jacobian", "expected 0 or 1, found " + std::to_string(jac.bytes[0]));
  b.jacobian = jac.bytes[0] == 1;

  const TensorField& ndf = r.field("ndf", TensorDtype::Float32, 2);
  r.require_table(ndf, 0);
  const TensorField& sigma = r.field("sigma", TensorDtype::Float32, 2);
  r.require_table(sigma, 0);
  const TensorField& vndf = r.field("vndf", TensorDtype::Float32, 4);
  r.require_dim(vndf, 0, np, "|phi_i|");
  r.require_dim(vndf, 1, nt, "|theta_i|");
  r.require_table(vndf, 2);
  const TensorField& lum = r.field("luminance", TensorDtype::Float32, 4);
  r.require_dim(lum, 0, np, "|phi_i|");
  r.require_dim(lum, 1, nt, "|theta_i|");
  r.require_table(lum, 2);
  r.require_dim(lum, 3, lum.shape[2], "square sample grid");
  const TensorField& val = r.field(values_name, TensorDtype::Float32, 5);
  r.require_dim(val, 0, np, "|phi_i|");
  r.require_dim(val, 1, nt, "|theta_i|");
  r.require_dim(val, 2, lambda_axis.size(), b.spectral ? "|wavelengths|" : "R, G, B");
  r.require_dim(val, 3, lum.shape[2], "the luminance grid");
  r.require_dim(val, 4, lum.shape[3], "the luminance grid");

  if (np > 2) {
    const double span = b.phi_i.back() - b.phi_i.front();
    const double red = std::rint(2 * kPi / span);
    if (red != 1 && red != 2 && red != 4)
      r.fail("phi_i", "nodes span " + std::to_string(span) + " rad, expected 2 pi, pi or pi/2 (symmetry reduction 1, 2 or 4), found reduction " + std::to_string(red));
    b.reduction = static_cast<int>(red);
  }

  const auto h = [](const TensorField& f, size_t d) { return static_cast<int>(f.shape[d]); };
  b.ndf = BilinearSlices(r.finite_values(ndf, false), h(ndf, 1), h(ndf, 0), ParameterGrid());
  std::vector<double> sv = r.finite_values(sigma, false);
  if (b.jacobian)
    for (size_t k = 0; k < sv.size(); ++k)
      if (!(sv[k] > 0)) r.fail("sigma", "value " + std::to_string(k) + ": expected > 0 (jacobian is 1, sigma divides), found " + std::to_string(sv[k]));
  b.sigma = BilinearSlices(std::move(sv), h(sigma, 1), h(sigma, 0), ParameterGrid());
  (void)r.finite_values(lum, true);
  try {
    b.vndf = MarginalWarp2D(r.finite_values(vndf, true), h(vndf, 3), h(vndf, 2), ParameterGrid({b.phi_i, b.theta_i}));
  } catch (const ArgumentError& e) {
    r.fail("vndf", e.what());
  }
  b.sample_width = h(val, 4);
  b.sample_height = h(val, 3);
  std::vector<double> values = r.finite_values(val, false);
  const std::size_t table = static_cast<std::size_t>(b.sample_width) * static_cast<std::size_t>(b.sample_height);
  for (std::size_t at = 0; at + table <= values.size(); at += table)
    b.noise_sigma.push_back(table_noise_sigma(values.data() + at, b.sample_height, b.sample_width));
  b.values = BilinearSlices(std::move(values), b.sample_width, b.sample_height, ParameterGrid({b.phi_i, b.theta_i, lambda_axis}));
  return b;
}

RglModel::RglModel(std::shared_ptr<const RglBsdf> bsdf, std::vector<double> lambdas, std::string spec)
    : bsdf_(std::move(bsdf)), lambdas_(std::move(lambdas)), spec_(std::move(spec)) {
  if (lambdas_.empty()) throw ArgumentError("RGL material: no channel selected");
}

RglModel::Lookup RglModel::lookup(Eigen::Vector3d wi, Eigen::Vector3d wr) const {
  const RglBsdf& b = *bsdf_;
  Lookup l;
  if (!(wi.z() > 0 && wr.z() > 0)) return l;
  if (b.reduction >= 2) {
    const double sy = wi.y(), sx = b.reduction == 4 ? wi.x() : sy;
    const double fx = sx >= 0 ? -1.0 : 1.0, fy = sy >= 0 ? -1.0 : 1.0;
    wi.x() *= fx;
    wr.x() *= fx;
    wi.y() *= fy;
    wr.y() *= fy;
  }
  const Eigen::Vector3d m = (wi + wr).normalized();
  const double theta_i = elevation(wi.x(), wi.y(), wi.z()), phi_i = std::atan2(wi.y(), wi.x());
  const double theta_m = elevation(m.x(), m.y(), m.z()), phi_m = std::atan2(m.y(), m.x());
  const double um_x = theta_to_u(theta_m);
  double um_y = phi_to_u(b.isotropic() ? phi_m - phi_i : phi_m);
  um_y -= std::floor(um_y);
  const double params[3] = {phi_i, theta_i, 0.0};
  l.above = true;
  l.phi_i = phi_i;
  l.theta_i = theta_i;
  l.sample = b.vndf.invert(um_x, um_y, b.vndf.grid().blend(params));
  l.scale = 1.0 / std::max(wr.z(), kGrazingCosFloor);
  if (b.jacobian) l.scale *= b.ndf.eval(um_x, um_y, nullptr) / (4.0 * b.sigma.eval(theta_to_u(theta_i), phi_to_u(phi_i), nullptr));
  return l;
}

void RglModel::eval(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const { fill(wi, wr, out, false); }

void RglModel::noise_sigma(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) const { fill(wi, wr, out, true); }

double RglModel::node_noise(const double* params) const {
  const RglBsdf& b = *bsdf_;
  const SliceBlend blend = b.values.grid().blend(params);
  double variance = 0.0;
  for (int k = 0; k < blend.count; ++k) {
    const double s = b.noise_sigma[static_cast<size_t>(blend.slice[static_cast<size_t>(k)])];
    variance += blend.weight[static_cast<size_t>(k)] * s * s;
  }
  return std::sqrt(variance);
}

void RglModel::fill(const RowMatrix3d& wi_all, const RowMatrix3d& wr_all, Eigen::Ref<Eigen::MatrixXd> out, bool noise) const {
  check_pair_shapes(wi_all, wr_all, out, channels());
  const RglBsdf& b = *bsdf_;
  const int nc = channels();
#pragma omp parallel for schedule(static) if (wi_all.rows() > 256)
  for (Eigen::Index row = 0; row < wi_all.rows(); ++row) {
    const Lookup l = lookup(wi_all.row(row).transpose(), wr_all.row(row).transpose());
    if (!l.above) {
      out.row(row).setZero();
      continue;
    }
    for (int c = 0; c < nc; ++c) {
      const double p[3] = {l.phi_i, l.theta_i, lambdas_[static_cast<size_t>(c)]};
      out(row, c) = (noise ? node_noise(p) : b.values.eval(l.sample.x(), l.sample.y(), p)) * l.scale;
    }
  }
}

}  // namespace icobrdf
