// icobrdf eval: values of a BRDF SOURCE at direction pairs.
//
//   icobrdf eval SOURCE --at PAIRS.csv [--radians]
//
// SOURCE: model:NAME[:key=value,...] (icobrdf models lists them; sums "model:0.8*lambert+0.2*ggx:alpha=0.1")
// or any kind registered in cli/source_evaluator.hpp. PAIRS.csv: header theta_i,phi_i,theta_r,phi_r, degrees
// unless --radians (io/direction_csv.hpp). Output: CSV with a header of one column per channel ("f" or
// "f_r,f_g,f_b"), one line per input row, f in 1/sr, shortest round-trip decimals. Delta parts (mirror,
// retroreflector) have no pointwise value: the regular part is printed and a note goes to stderr.
// Nothing is printed to stdout unless every row was evaluated.
#include <fmt/core.h>

#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "cli/source_evaluator.hpp"
#include "io/direction_csv.hpp"

namespace icobrdf::cli {

namespace {

struct EvalOptions {
  std::string source;
  std::string at;
  bool radians = false;
};

void run_eval(const EvalOptions& o) {
  const PairEvaluator evaluator = open_pair_evaluator(o.source);
  const DirectionPairs pairs = read_direction_pairs_csv(o.at, o.radians);
  Eigen::MatrixXd values(pairs.wi.rows(), static_cast<Eigen::Index>(evaluator.columns.size()));
  evaluator.eval(pairs.wi, pairs.wr, values);
  for (const auto& note : evaluator.notes) std::cerr << "icobrdf: note: " << evaluator.description << ": " << note << "\n";
  std::string text;
  for (std::size_t c = 0; c < evaluator.columns.size(); ++c) text += (c ? "," : "") + evaluator.columns[c];
  text += "\n";
  for (Eigen::Index r = 0; r < values.rows(); ++r) {
    for (Eigen::Index c = 0; c < values.cols(); ++c) text += fmt::format(c ? ",{}" : "{}", values(r, c));
    text += "\n";
  }
  std::cout << text;
}

void add_eval_command(CLI::App& app) {
  auto opts = std::make_shared<EvalOptions>();
  auto* cmd = app.add_subcommand("eval", "Print f [1/sr] of a SOURCE (model:NAME[:key=value,...]) at direction pairs");
  cmd->add_option("source", opts->source, "model:NAME[:key=value,...], e.g. model:ggx:alpha=0.2,f0=0.04")->required();
  cmd->add_option("--at", opts->at, "CSV with header theta_i,phi_i,theta_r,phi_r (degrees)")->required();
  cmd->add_flag("--radians", opts->radians, "Angles in PAIRS.csv are in radians");
  cmd->callback([opts] { run_eval(*opts); });
}

const CommandRegistrar kRegistrar("eval", add_eval_command);

}  // namespace
}  // namespace icobrdf::cli
