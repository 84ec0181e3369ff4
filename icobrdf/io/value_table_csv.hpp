#pragma once
// A table of values as CSV text: a header of column names, then one line per row with the shortest
// round-trip decimal of each value (fmt's "{}"), so that reading the text back gives the same doubles.
#include <Eigen/Core>
#include <string>
#include <vector>

namespace icobrdf {

// `values` is rows x columns.size().
std::string value_table_csv(const std::vector<std::string>& columns, const Eigen::MatrixXd& values);

}  // namespace icobrdf
