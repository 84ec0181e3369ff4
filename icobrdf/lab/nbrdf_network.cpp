#include "icobrdf/lab/nbrdf_network.hpp"

#include <algorithm>
#include <cmath>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/h5_file.hpp"

namespace icobrdf::lab {
namespace {

// One dense layer's kernel (in x out) and bias (out) from dense_k/dense_k/.
void read_layer(const h5::Group& root, int k, int in, int out, Eigen::MatrixXd& w, Eigen::RowVectorXd& b) {
  const std::string name = "dense_" + std::to_string(k);
  if (!root.has(name) || !root.is_group(name)) root.fail(name, "missing layer group, expected a Keras dense layer");
  const h5::Group outer = root.open_group(name);
  if (!outer.has(name) || !outer.is_group(name)) outer.fail(name, "missing weights group, expected " + name + "/" + name);
  const h5::Group g = outer.open_group(name);
  const h5::ReadLimits limits;
  if (g.dataset_type("kernel:0", limits) != h5::Type::float32) g.fail("kernel:0", "element type, expected float32");
  if (g.dataset_type("bias:0", limits) != h5::Type::float32) g.fail("bias:0", "element type, expected float32");
  const h5::Array<double> kernel = g.read_real("kernel:0", {in, out}, limits);
  const h5::Array<double> bias = g.read_real("bias:0", {out}, limits);
  w.resize(in, out);
  for (int r = 0; r < in; ++r)
    for (int c = 0; c < out; ++c) w(r, c) = kernel.data[static_cast<size_t>(r) * out + c];
  b = Eigen::Map<const Eigen::RowVectorXd>(bias.data.data(), out);
  if (!w.allFinite() || !b.allFinite()) g.fail("kernel:0", "non-finite weight, expected finite numbers");
}

}  // namespace

NbrdfNetwork read_nbrdf_network(const std::string& path) {
  const h5::ReadFile file = h5::ReadFile::open(path);
  const h5::Group root = file.root();
  NbrdfNetwork n;
  n.path = path;
  read_layer(root, 1, 6, kNbrdfHidden, n.w1, n.b1);
  read_layer(root, 2, kNbrdfHidden, kNbrdfHidden, n.w2, n.b2);
  read_layer(root, 3, kNbrdfHidden, 3, n.w3, n.b3);
  return n;
}

Eigen::MatrixXd NbrdfNetwork::eval(const RowMatrix3d& wi, const RowMatrix3d& wr) const {
  if (wi.rows() != wr.rows())
    throw ArgumentError("nbrdf eval: " + std::to_string(wi.rows()) + " w_i rows vs " + std::to_string(wr.rows()) + " w_r rows, expected equal");
  const Eigen::Index n = wi.rows();
  Eigen::MatrixXd x(n, 6);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Vector3d a = wr.row(k).transpose(), b = wi.row(k).transpose();  // `a`: the slot rotated into d
    const Eigen::Vector3d h = (a + b).normalized();
    double th = std::acos(std::clamp(h.z(), -1.0, 1.0)), ph = std::atan2(h.y(), h.x());
    if (h.z() > kNbrdfPoleZ) th = ph = 0.0;
    const double cp = std::cos(ph), sp = std::sin(ph), ct = std::cos(th), st = std::sin(th);
    const double x1 = a.x() * cp + a.y() * sp, y1 = a.y() * cp - a.x() * sp, z1 = a.z();  // R_z(-phi_h)
    Eigen::Vector3d d(x1 * ct - z1 * st, y1, z1 * ct + x1 * st);                        // R_y(-theta_h)
    d.normalize();
    x.row(k) << st, 0.0, ct, d.x(), d.y(), d.z();
  }
  Eigen::MatrixXd a1 = x * w1;
  a1.rowwise() += b1;
  a1 = a1.cwiseMax(0.0);
  Eigen::MatrixXd a2 = a1 * w2;
  a2.rowwise() += b2;
  a2 = a2.cwiseMax(0.0);
  Eigen::MatrixXd f = a2 * w3;
  f.rowwise() += b3;
  f = (f.array().exp() - 1.0).matrix();
  for (Eigen::Index k = 0; k < n; ++k)
    if (wi(k, 2) <= 0.0 || wr(k, 2) <= 0.0) f.row(k).setZero();
  return f;
}

}  // namespace icobrdf::lab
