#include "icobrdf/core/projection/reflection.hpp"

#include <string>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

void check_shape(const Eigen::MatrixXd& lut, const Grid& g, const char* what) {
  if (lut.rows() != g.cells() || lut.cols() != g.cells())
    throw ArgumentError(std::string(what) + ": LUT is " + std::to_string(lut.rows()) + " x " + std::to_string(lut.cols()) +
                        ", expected " + std::to_string(g.cells()) + " x " + std::to_string(g.cells()) + " for the grid");
}

}  // namespace

Eigen::VectorXd reflect_radiance(const Eigen::MatrixXd& lut, bool cosine, const Grid& g, const Eigen::VectorXd& incident) {
  check_shape(lut, g, "reflect");
  if (incident.size() != g.cells())
    throw ArgumentError("reflect: incident radiance has " + std::to_string(incident.size()) + " entries, expected " + std::to_string(g.cells()));
  Eigen::VectorXd weight = g.solid_angles.cwiseProduct(incident);
  if (!cosine) weight = weight.cwiseProduct(cell_mean_cosines(g));
  return lut.transpose() * weight;
}

Eigen::VectorXd directional_albedo(const Eigen::MatrixXd& lut, bool cosine, const Grid& g) {
  check_shape(lut, g, "albedo");
  const Eigen::VectorXd d = cell_mean_cosines(g);
  Eigen::VectorXd a = lut * d.cwiseProduct(g.solid_angles);
  if (cosine) a = a.cwiseQuotient(d);
  return a;
}

WhiteFurnace white_furnace(const Eigen::MatrixXd& lut, bool cosine, const Grid& g) {
  const Eigen::VectorXd a = directional_albedo(lut, cosine, g);
  WhiteFurnace w;
  Eigen::Index worst = 0;
  w.max_albedo = a.maxCoeff(&worst);
  w.worst_cell = static_cast<int>(worst);
  w.mean_albedo = a.dot(g.solid_angles) / g.solid_angles.sum();
  return w;
}

}  // namespace icobrdf
