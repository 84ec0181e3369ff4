#pragma once
// Directions for tests of the basis kernels: uniform in cos(theta) and phi over the hemisphere (seeded), with
// the hard cases put in: the pole (rho = 0), the horizon (z = 0, rho = 1) at several azimuths, and z slightly
// negative (-1e-13, taken as the horizon).
#include <Eigen/Core>

#include <cmath>
#include <iterator>
#include <random>

#include "icobrdf/core/grid/grid.hpp"

namespace icobrdf::test {

inline RowMatrix3d hard_directions(int count, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  RowMatrix3d d(count, 3);
  for (int k = 0; k < count; ++k) {
    const double z = u(rng), s = std::sqrt(1.0 - z * z), p = 2.0 * M_PI * u(rng);
    d.row(k) << s * std::cos(p), s * std::sin(p), z;
  }
  const double neg = -1e-13, s = std::sqrt(1.0 - neg * neg);
  const Eigen::RowVector3d hard[] = {{0.0, 0.0, 1.0},  {1.0, 0.0, 0.0},        {0.0, -1.0, 0.0},
                                     {-1.0, 0.0, 0.0}, {std::cos(2.0), std::sin(2.0), 0.0},
                                     {s * std::cos(0.7), s * std::sin(0.7), neg}, {-s, 0.0, neg}};
  for (int k = 0; k < static_cast<int>(std::size(hard)) && k < count; ++k) d.row((k * 7) % count) = hard[k];
  return d;
}

}  // namespace icobrdf::test
