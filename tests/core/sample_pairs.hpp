#pragma once
// Direction pairs for tests of sample fits: uniform in cos(theta) and phi over the hemisphere, seeded; and
// seeded normal vectors (coefficients, noise).
#include <Eigen/Core>

#include <cmath>
#include <random>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf::test {

inline Eigen::Vector3d random_direction(std::mt19937& g) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = u(g), phi = 2 * M_PI * u(g), s = std::sqrt(1 - z * z);
  return {s * std::cos(phi), s * std::sin(phi), z};
}

struct Pairs {
  RowMatrix3d wi, wr;
};

inline Pairs random_pairs(int count, unsigned seed) {
  std::mt19937 g(seed);
  Pairs p;
  p.wi.resize(count, 3);
  p.wr.resize(count, 3);
  for (int i = 0; i < count; ++i) {
    p.wi.row(i) = random_direction(g).transpose();
    p.wr.row(i) = random_direction(g).transpose();
  }
  return p;
}

// n standard normal values, seeded.
inline Eigen::VectorXd random_vector(Eigen::Index n, unsigned seed) {
  std::mt19937 g(seed);
  std::normal_distribution<double> nd(0.0, 1.0);
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) v[i] = nd(g);
  return v;
}

}  // namespace icobrdf::test
