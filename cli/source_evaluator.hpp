#pragma once
// Evaluating a SOURCE at direction pairs: the extension point for the kinds of SOURCE that `icobrdf eval`
// (and any command that only needs values of f) accepts.
//
// A source kind registers an opener (self-registration, like the subcommands):
//   static const icobrdf::cli::SourceKindRegistrar reg("spectrum", [](const std::string& source)
//       -> std::optional<icobrdf::cli::PairEvaluator> { if (!looks_like_mine(source)) return std::nullopt; ... });
// open_pair_evaluator() asks the openers in name order; the first one returning an evaluator wins. An
// opener returns nullopt when the SOURCE is not of its kind and throws (ArgumentError, InputError,
// IoError, ...) when it is but cannot be opened. Built in: kind "model" for "model:NAME[:key=value,...]".
#include <Eigen/Core>

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/grid.hpp"

namespace icobrdf::cli {

struct PairEvaluator {
  std::string description;           // canonical form of the source, e.g. "model:lambert:albedo=1"
  std::vector<std::string> columns;  // output column names, one per channel (channel_column_names)
  std::vector<std::string> notes;    // remarks for stderr (e.g. delta parts not represented in values)
  // f [1/sr] at rows of wi, wr (unit vectors, rows x 3) into out (rows x columns.size()).
  std::function<void(const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out)> eval;
};

using SourceOpener = std::function<std::optional<PairEvaluator>(const std::string& source)>;

struct SourceKindRegistrar {
  SourceKindRegistrar(const std::string& kind, SourceOpener opener);
};

// ArgumentError naming the source and the known kinds when no opener accepts it.
PairEvaluator open_pair_evaluator(const std::string& source);

// "f" for 1 channel, "f_r,f_g,f_b" for 3, "f_0".."f_{n-1}" otherwise.
std::vector<std::string> channel_column_names(int channels);

}  // namespace icobrdf::cli
