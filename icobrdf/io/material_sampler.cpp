#include "icobrdf/io/material_sampler.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/basis/horizon.hpp"

namespace icobrdf {
namespace {

// Directions are normalized by the caller; 1e-10 on the norm allows any rounding of a normalization (as
// CellLocator) while rejecting vectors that were never normalized.
constexpr double kUnitTolerance = 1e-10;

std::string degrees(const Eigen::Vector3d& w) {
  const Angles a = angles_from_direction(w);
  char buf[64];
  std::snprintf(buf, sizeof buf, "(theta %.6g, phi %.6g deg)", a.theta * 180 / M_PI, a.phi * 180 / M_PI);
  return buf;
}

void check_unit(const Eigen::Vector3d& w, const char* what) {
  if (!w.allFinite() || std::abs(w.norm() - 1.0) > kUnitTolerance || w.z() < -kHorizonSlack) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "%s: expected a unit vector with z >= 0, found (%.17g, %.17g, %.17g)", what, w.x(), w.y(), w.z());
    throw ArgumentError(buf);
  }
}

}  // namespace

MaterialSampler::MaterialSampler(std::shared_ptr<const BrdfSource> source, int level, LutSampling cell_value)
    : source_(std::move(source)), sampler_(level), cell_value_(cell_value) {
  if (!source_) throw ArgumentError("MaterialSampler: no source");
}

IncidentDistribution MaterialSampler::distribution(const Eigen::Vector3d& wi) const {
  check_unit(wi, "sample: w_i");
  const Grid& g = sampler_.grid();
  const int n = g.cells();
  const bool centre = cell_value_ == LutSampling::CellCentre;
  const Eigen::Index points = centre ? n : static_cast<Eigen::Index>(g.cubature_offsets.back());
  const RowMatrix3d& wr = centre ? g.directions : g.cubature_points;
  RowMatrix3d wis(points, 3);
  wis.rowwise() = wi.transpose();
  const Eigen::MatrixXd f = source_->eval(wis, wr);
  const std::string where = source_->spec() + ": f(w_i = " + degrees(wi) + ", w_r)";
  Eigen::VectorXd value(points);  // mean over channels of max(f, 0), times cos(theta_r)
  for (Eigen::Index q = 0; q < points; ++q) {
    double s = 0;
    for (Eigen::Index c = 0; c < f.cols(); ++c) {
      const double v = f(q, c);
      if (!std::isfinite(v))
        throw UnsupportedError(where + " is " + std::to_string(v) + " at w_r = " + degrees(wr.row(q).transpose()) +
                               ", expected finite values to build the sampling distribution");
      s += std::max(v, 0.0);
    }
    value[q] = s / static_cast<double>(f.cols()) * std::max(wr(q, 2), 0.0);
  }
  Eigen::VectorXd mass(n);
  if (centre) {
    mass = value.cwiseProduct(g.solid_angles);
  } else {
    for (int k = 0; k < n; ++k) {
      double s = 0;
      for (auto q = g.cubature_offsets[k]; q < g.cubature_offsets[k + 1]; ++q) s += g.cubature_weights[q] * value[q];
      mass[k] = s;
    }
  }
  double total = 0;  // a plain loop: Eigen's AVX-512 sum trips gcc 12's -Wmaybe-uninitialized here
  for (int k = 0; k < n; ++k) total += mass[k];
  if (!(total > 0))
    throw UnsupportedError("max(" + where + ", 0) cos(theta_r) is 0 at every one of the " + std::to_string(points) + " " +
                           (centre ? "cell centres" : "cubature points") + " of level " + std::to_string(level()) +
                           (source_->has_delta() ? " (its delta part cannot be sampled)" : "") + ": nothing to sample");
  return IncidentDistribution{wi, CellDistribution(mass, where), total};
}

MaterialSamples MaterialSampler::draw(const IncidentDistribution& dist, const Eigen::VectorXd& u1, const Eigen::VectorXd& u2) const {
  if (u1.size() != u2.size())
    throw ArgumentError("sample: u1 has " + std::to_string(u1.size()) + " values, u2 " + std::to_string(u2.size()));
  const Eigen::Index n = u1.size();
  for (Eigen::Index i = 0; i < n; ++i)
    if (!(u1[i] >= 0 && u1[i] <= 1 && u2[i] >= 0 && u2[i] <= 1))
      throw ArgumentError("sample: (u1, u2)[" + std::to_string(i) + "] = (" + std::to_string(u1[i]) + ", " + std::to_string(u2[i]) +
                          "), expected uniform numbers in [0, 1]");
  MaterialSamples out;
  out.directions.resize(n, 3);
  out.pdf.resize(n);
  out.cells.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const DirectionSample s = sampler_.sample(dist.cells, u1[i], u2[i]);
    out.directions.row(i) = s.direction.transpose();
    out.pdf[i] = s.pdf;
    out.cells[i] = s.cell;
  }
  out.weight.resize(n, 0);
  return out;
}

void MaterialSampler::weigh(const IncidentDistribution& dist, MaterialSamples& drawn) const {
  const Eigen::Index n = drawn.directions.rows();
  RowMatrix3d wis(n, 3);
  wis.rowwise() = dist.wi.transpose();
  drawn.weight = source_->eval(wis, drawn.directions);
  for (Eigen::Index i = 0; i < n; ++i) drawn.weight.row(i) *= drawn.directions(i, 2) / drawn.pdf[i];
}

MaterialSamples MaterialSampler::sample(const IncidentDistribution& dist, const Eigen::VectorXd& u1, const Eigen::VectorXd& u2) const {
  MaterialSamples out = draw(dist, u1, u2);
  weigh(dist, out);
  return out;
}

Eigen::VectorXd MaterialSampler::pdf(const IncidentDistribution& dist, const RowMatrix3d& wr) const {
  return sampler_.pdf(dist.cells, wr);
}

}  // namespace icobrdf
