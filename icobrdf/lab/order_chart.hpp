#pragma once
// The chart the lab draws most: a quantity against the expansion order N (integer x axis), on a log y axis.
#include <string>

#include "icobrdf/plot/line_chart.hpp"

namespace icobrdf::lab {

inline plot::ChartOptions order_chart(const std::string& title, const std::string& y_label) {
  plot::ChartOptions o;
  o.title = title;
  o.x_label = "order N";
  o.y_label = y_label;
  o.log_y = true;
  o.integer_x = true;
  return o;
}

}  // namespace icobrdf::lab
