#pragma once
// Direct quadrature without matrices (icobrdf/core/projection/direct_projection.hpp: per cubature pair, the modes are evaluated
// and the coefficients accumulated) against the matrix path (B sampled once, C = P^T F P by streaming), for
// one model on a centre-sampled equal-area grid: times in seconds, speed ratios, and the agreement (max
// entry difference relative to the max entry). With one point per cell both compute the same sums, so they
// must agree to rounding.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace icobrdf::lab {

// Timed repetitions of each path (the best is reported; the first run also pays for thread start-up and
// first touch of the buffers).
inline constexpr int kDirectRepeats = 2;
// The model of the comparison.
inline constexpr const char* kDirectModel = "ggx:alpha=0.2";

struct DirectCase {
  int level, order;
};

// Measures one case; `row` receives the markdown table row (see direct_vs_matrix_header), the return
// value the JSON figures.
nlohmann::json direct_vs_matrix(const DirectCase& dc, std::vector<std::string>& row);

// The header of the rows direct_vs_matrix fills.
std::vector<std::string> direct_vs_matrix_header();

}  // namespace icobrdf::lab
