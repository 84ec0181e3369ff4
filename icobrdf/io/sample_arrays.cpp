#include "icobrdf/io/sample_arrays.hpp"

#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/unit_directions.hpp"

namespace icobrdf {

namespace {

// Every direction component lies in [-1, 1] and is compared exactly: equal pairs are equal vectors.
using PairKey = std::array<double, 6>;

std::string rows_text(Eigen::Index n) { return std::to_string(n) + (n == 1 ? " row" : " rows"); }

void check_shapes(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values, const Eigen::VectorXd& weights) {
  const Eigen::Index n = wi.rows();
  if (n == 0) throw ArgumentError("samples: wi has no rows, expected at least one sample");
  if (wr.rows() != n) throw ArgumentError("samples: wr has " + rows_text(wr.rows()) + ", expected one per row of wi (" + rows_text(n) + ")");
  if (values.rows() != n)
    throw ArgumentError("samples: values has " + rows_text(values.rows()) + ", expected one per row of wi (" + rows_text(n) + ")");
  if (values.cols() < 1) throw ArgumentError("samples: values has no columns, expected one per channel");
  if (weights.size() != 0 && weights.size() != n)
    throw ArgumentError("samples: weights has " + std::to_string(weights.size()) + " values, expected one per row of wi (" +
                        rows_text(n) + ")");
  require_unit_directions(wi, "samples: wi", true);
  require_unit_directions(wr, "samples: wr", true);
  for (Eigen::Index k = 0; k < n; ++k) {
    if (!values.row(k).allFinite()) throw ArgumentError("samples: values row " + std::to_string(k) + " is not finite, expected f in 1/sr");
    if (weights.size() != 0 && !(std::isfinite(weights[k]) && weights[k] >= 0))
      throw ArgumentError("samples: weights[" + std::to_string(k) + "] = " + std::to_string(weights[k]) + ", expected a finite weight >= 0");
  }
}

}  // namespace

BrdfSamples samples_from_arrays(const RowMatrix3d& wi, const RowMatrix3d& wr, const Eigen::MatrixXd& values,
                                const Eigen::VectorXd& weights) {
  check_shapes(wi, wr, values, weights);
  const Eigen::Index n = wi.rows();
  const auto ch = values.cols();
  std::map<PairKey, Eigen::Index> index;  // pair -> sample
  std::vector<std::vector<Eigen::Index>> rows;  // per sample: its rows, the first one first
  BrdfSamples s;
  s.path = "arrays";
  s.channels = static_cast<int>(ch);
  s.rows = n;
  for (Eigen::Index k = 0; k < n; ++k) {
    s.negative_values += (values.row(k).array() < 0).count();
    const PairKey key{wi(k, 0), wi(k, 1), wi(k, 2), wr(k, 0), wr(k, 1), wr(k, 2)};
    const auto [it, added] = index.emplace(key, static_cast<Eigen::Index>(rows.size()));
    if (added) rows.emplace_back();
    else ++s.duplicates_merged;
    rows[static_cast<size_t>(it->second)].push_back(k);
  }
  const auto m = static_cast<Eigen::Index>(rows.size());
  s.wi.resize(m, 3);
  s.wr.resize(m, 3);
  s.values.resize(m, ch);
  s.weights.resize(m);
  for (Eigen::Index j = 0; j < m; ++j) {
    const std::vector<Eigen::Index>& r = rows[static_cast<size_t>(j)];
    s.wi.row(j) = wi.row(r[0]);
    s.wr.row(j) = wr.row(r[0]);
    s.lines.push_back(static_cast<int>(r[0]) + 1);
    // One row: its value as given. Several: their weighted mean (the first row's value when every weight is 0).
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(ch);
    double total = 0;
    for (const Eigen::Index k : r) {
      const double w = weights.size() ? weights[k] : 1.0;
      sum += w * values.row(k).transpose();
      total += w;
    }
    if (r.size() == 1 || total == 0) s.values.row(j) = values.row(r[0]);
    else s.values.row(j) = (sum / total).transpose();
    s.weights[j] = total;
  }
  return s;
}

}  // namespace icobrdf
