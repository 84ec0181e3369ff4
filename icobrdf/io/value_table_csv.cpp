#include "icobrdf/io/value_table_csv.hpp"

#include <fmt/core.h>

namespace icobrdf {

std::string value_table_csv(const std::vector<std::string>& columns, const Eigen::MatrixXd& values) {
  std::string text;
  for (std::size_t c = 0; c < columns.size(); ++c) text += (c ? "," : "") + columns[c];
  text += "\n";
  for (Eigen::Index r = 0; r < values.rows(); ++r) {
    for (Eigen::Index c = 0; c < values.cols(); ++c) text += fmt::format(c ? ",{}" : "{}", values(r, c));
    text += "\n";
  }
  return text;
}

}  // namespace icobrdf
