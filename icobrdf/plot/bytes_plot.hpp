#pragma once
// Error against bytes of a bank material's candidates (icobrdf/pipeline/bank_candidates.hpp): log-log, x = the
// bytes a representation stores, y = its relative L2 error over the held-out pairs (the material's metric).
// Per representation: every point the build reached (markers) and its lower envelope (line: the lowest error
// at or below each size); the target as a dashed horizontal line; the candidate the bank stores marked by a
// black diamond. Points are drawn as stored; nothing is refitted.
#include <string>
#include <vector>

#include "icobrdf/pipeline/bank_candidates.hpp"
#include "icobrdf/plot/line_chart.hpp"

namespace icobrdf::plot {

struct BytesFigure {
  ChartFrame frame;
  std::vector<std::string> representations;  // one curve each, in name order
  int points = 0;
  int width = 0, height = 0;
};

// Points of one representation on its lower envelope, by bytes ascending: each has a lower error than every
// point with fewer bytes.
std::vector<CandidatePoint> lower_envelope(std::vector<CandidatePoint> points);

// InputError when the material holds no candidates (a bank built before they were stored).
BytesFigure plot_bytes(const std::string& label, const BankMaterialCandidates& material, const std::string& path);

}  // namespace icobrdf::plot
