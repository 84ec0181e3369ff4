#pragma once
// Independent hemisphere quadrature for the BRDF model tests (shares no code with the library):
// Gauss-Legendre nodes from the Golub-Welsch eigenproblem, composite in theta (panels), and the uniform
// (trapezoidal, spectrally accurate for periodic integrands) rule in phi.
#include <Eigen/Dense>

#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "icobrdf/core/models/brdf_model.hpp"

namespace icobrdf::test {

struct GaussRule {
  std::vector<double> x, w;  // on [-1, 1]
};

inline GaussRule gauss_legendre_gw(int n) {
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(n, n);
  for (int k = 1; k < n; ++k) j(k, k - 1) = j(k - 1, k) = k / std::sqrt(4.0 * k * k - 1.0);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(j);
  GaussRule r;
  for (int k = 0; k < n; ++k) {
    r.x.push_back(es.eigenvalues()(k));
    r.w.push_back(2.0 * es.eigenvectors()(0, k) * es.eigenvectors()(0, k));
  }
  return r;
}

// A quadrature rule on the upper hemisphere: sum_k weights(k) fn(dirs.row(k)) ~ integral of fn dOmega.
struct GradedHemisphereRule {
  RowMatrix3d dirs;
  Eigen::VectorXd weights;
};

// Tensor product of composite 8-point Gauss rules:
//  theta: `theta_panels` equal panels, the last one split geometrically towards the horizon (distances
//         dtheta/10 ... dtheta/1e4) to resolve grazing lobes;
//  phi:   if `phi_focus` is a number, panels graded geometrically towards that azimuth (edges at
//         phi_focus +- pi x {1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, ..., 0.9, 1}), where grazing lobes are
//         narrow, with edges at phi_focus +- pi/2 where Oren-Nayar-type max(0, cos) kinks sit; if NaN,
//         the uniform (trapezoidal, spectrally accurate for smooth periodic integrands) rule with 512 points.
// `split` subdivides every panel in that many equal parts and multiplies the uniform phi count (refinement).
inline GradedHemisphereRule graded_hemisphere_rule(int theta_panels, int split, double phi_focus) {
  static const GaussRule g = gauss_legendre_gw(8);
  const auto refine = [&](const std::vector<double>& e) {
    std::vector<double> out;
    for (std::size_t k = 0; k + 1 < e.size(); ++k)
      for (int q = 0; q < split; ++q) out.push_back(e[k] + (e[k + 1] - e[k]) * q / split);
    out.push_back(e.back());
    return out;
  };
  const auto gauss_on = [&](const std::vector<double>& e, std::vector<double>& x, std::vector<double>& w) {
    for (std::size_t p = 0; p + 1 < e.size(); ++p)
      for (std::size_t k = 0; k < g.x.size(); ++k) {
        x.push_back(0.5 * (e[p] + e[p + 1]) + 0.5 * (e[p + 1] - e[p]) * g.x[k]);
        w.push_back(0.5 * (e[p + 1] - e[p]) * g.w[k]);
      }
  };
  const double dth = 0.5 * M_PI / theta_panels;
  std::vector<double> te;
  for (int p = 0; p < theta_panels; ++p) te.push_back(dth * p);
  for (double f : {0.1, 0.01, 1e-3, 1e-4}) te.push_back(0.5 * M_PI - dth * f);
  te.push_back(0.5 * M_PI);
  std::vector<double> thetas, tw, phis, pw;
  gauss_on(refine(te), thetas, tw);
  if (std::isnan(phi_focus)) {
    const int n = 512 * split;
    for (int q = 0; q < n; ++q) {
      phis.push_back(2.0 * M_PI * (q + 0.5) / n);
      pw.push_back(2.0 * M_PI / n);
    }
  } else {
    const std::vector<double> rel = {1e-4, 1e-3, 3e-3, 1e-2, 3e-2, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
    std::vector<double> pe;
    for (auto it = rel.rbegin(); it != rel.rend(); ++it) pe.push_back(phi_focus - M_PI * *it);
    pe.push_back(phi_focus);
    for (double r : rel) pe.push_back(phi_focus + M_PI * r);
    gauss_on(refine(pe), phis, pw);
  }
  GradedHemisphereRule rule;
  rule.dirs.resize(static_cast<Eigen::Index>(thetas.size() * phis.size()), 3);
  rule.weights.resize(rule.dirs.rows());
  Eigen::Index k = 0;
  for (std::size_t a = 0; a < thetas.size(); ++a)
    for (std::size_t b = 0; b < phis.size(); ++b, ++k) {
      const double st = std::sin(thetas[a]);
      rule.dirs.row(k) << st * std::cos(phis[b]), st * std::sin(phis[b]), std::cos(thetas[a]);
      rule.weights(k) = tw[a] * st * pw[b];
    }
  return rule;
}

struct Converged {
  double value;       // the finer estimate
  double difference;  // |finer - coarser|
};

// Integral of a batch integrand (values at the rows of dirs) with the rule as given and with every panel
// split in two; the difference is the convergence check.
inline Converged refined_batch_integral(const std::function<Eigen::VectorXd(const RowMatrix3d&)>& fn, int theta_panels,
                                        double phi_focus) {
  const auto coarse_rule = graded_hemisphere_rule(theta_panels, 1, phi_focus);
  const auto fine_rule = graded_hemisphere_rule(theta_panels, 2, phi_focus);
  const double coarse = coarse_rule.weights.dot(fn(coarse_rule.dirs));
  const double fine = fine_rule.weights.dot(fn(fine_rule.dirs));
  return {fine, std::abs(fine - coarse)};
}

inline Converged refined_integral(const std::function<double(const Eigen::Vector3d&)>& fn, int theta_panels,
                                  double phi_focus) {
  return refined_batch_integral(
      [&](const RowMatrix3d& d) {
        Eigen::VectorXd v(d.rows());
        for (Eigen::Index k = 0; k < d.rows(); ++k) v(k) = fn(d.row(k).transpose());
        return v;
      },
      theta_panels, phi_focus);
}

// Directional albedo: integral of f(wi, wr) cos(theta_r) dOmega_r (regular part, channel 0), with the
// azimuthal grading centred on the mirror azimuth of wi.
inline Converged directional_albedo(const BrdfModel& m, const Eigen::Vector3d& wi, int theta_panels) {
  return refined_batch_integral(
      [&](const RowMatrix3d& wr) {
        RowMatrix3d wis(wr.rows(), 3);
        wis.rowwise() = wi.transpose();
        Eigen::MatrixXd f(wr.rows(), m.channels());
        m.eval(wis, wr, f);
        return Eigen::VectorXd(f.col(0).cwiseProduct(wr.col(2)));
      },
      theta_panels, std::atan2(-wi.y(), -wi.x()));
}

inline Eigen::Vector3d dir_deg(double theta_deg, double phi_deg) {
  const double t = theta_deg * M_PI / 180.0, p = phi_deg * M_PI / 180.0;
  if (theta_deg == 90.0) return {std::cos(p), std::sin(p), 0.0};  // exactly on the horizon
  return {std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t)};
}

// Deterministic direction pairs: random ones plus every combination of the hard polar angles
// (normal 0, 45, grazing 89.9 and exact horizon 90 degrees) at a few azimuths.
struct PairSet {
  RowMatrix3d wi, wr;
};
inline PairSet test_pairs(int random_count, unsigned seed = 1234) {
  std::vector<Eigen::Vector3d> a, b;
  std::uint64_t state = seed;
  auto uniform = [&]() {  // splitmix64 -> [0, 1)
    state += 0x9e3779b97f4a7c15ULL;
    std::uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
  };
  for (int k = 0; k < random_count; ++k) {
    a.push_back(dir_deg(std::acos(uniform()) * 180.0 / M_PI, 360.0 * uniform()));
    b.push_back(dir_deg(std::acos(uniform()) * 180.0 / M_PI, 360.0 * uniform()));
  }
  const double thetas[] = {0.0, 45.0, 89.9, 90.0};
  const double phis[] = {0.0, 37.0, 180.0, 250.0};
  for (double ti : thetas)
    for (double tr : thetas)
      for (double pi : {0.0, 90.0})
        for (double pr : phis) {
          a.push_back(dir_deg(ti, pi));
          b.push_back(dir_deg(tr, pr));
        }
  PairSet s;
  s.wi.resize(static_cast<Eigen::Index>(a.size()), 3);
  s.wr.resize(static_cast<Eigen::Index>(a.size()), 3);
  for (std::size_t k = 0; k < a.size(); ++k) {
    s.wi.row(static_cast<Eigen::Index>(k)) = a[k].transpose();
    s.wr.row(static_cast<Eigen::Index>(k)) = b[k].transpose();
  }
  return s;
}

}  // namespace icobrdf::test
