#pragma once
// A reproducible dense matrix of entries uniform in [-1, 1] (Mersenne Twister, column by column), for tests of
// the dense kernels.
#include <Eigen/Core>

#include <random>

namespace icobrdf::test_support {

inline Eigen::MatrixXd random_matrix(Eigen::Index rows, Eigen::Index cols, unsigned seed) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd m(rows, cols);
  for (Eigen::Index j = 0; j < cols; ++j)
    for (Eigen::Index i = 0; i < rows; ++i) m(i, j) = u(g);
  return m;
}

}  // namespace icobrdf::test_support
