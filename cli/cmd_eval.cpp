// icobrdf eval: values of a BRDF SOURCE at direction pairs.
//   icobrdf eval SOURCE --at PAIRS.csv [--radians]
// SOURCE: model:NAME[:key=value,...] (icobrdf models lists them; sums "model:0.8*lambert+0.2*ggx:alpha=0.1")
// or any other SOURCE that icobrdf/io/brdf_source.hpp opens. PAIRS.csv: header theta_i,phi_i,theta_r,phi_r, sza,vza,raa, sza,saa,vza,vaa or SCATMECH's
// thetai,thetas,phis[,rotation], signed theta accepted, degrees unless --radians (icobrdf/io/direction_csv.hpp). Output: CSV with a header of one column per channel ("f" or
// "f_r,f_g,f_b"; a source naming its channels gives "f_" + name, e.g. "f_550nm" for a spectral RGL material), one line per input row, f in 1/sr, shortest round-trip decimals. Delta parts (mirror,
// retroreflector) have no pointwise value: the regular part is printed and a note goes to stderr.
// Nothing is printed to stdout unless every row was evaluated and every value is finite (an overflow is an
// error, exit 4); negative f is reported as non-physical (icobrdf/pipeline/reflectance_check.hpp; error with --strict).
#include <fmt/core.h>

#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/direction_csv.hpp"
#include "icobrdf/io/value_table_csv.hpp"
#include "icobrdf/pipeline/reflectance_check.hpp"

namespace icobrdf::cli {

namespace {

struct EvalOptions {
  std::string source;
  std::string at;
  bool radians = false, strict = false;
};

void run_eval(const EvalOptions& o) {
  const auto source = open_source(o.source);
  const DirectionPairs pairs = read_direction_pairs_csv(o.at, o.radians);
  const Eigen::MatrixXd values = source->eval(pairs.wi, pairs.wr);
  check_reflectance(values, "eval " + quoted_text(source->spec()), "the evaluation at the pairs of " + o.at, "f", {o.strict, &std::cerr});
  for (const auto& note : source->notes()) std::cerr << "icobrdf: note: " << source->spec() << ": " << note << "\n";
  std::cout << value_table_csv(channel_column_names(*source), values);
}

void add_eval_command(CLI::App& app) {
  auto opts = std::make_shared<EvalOptions>();
  auto* cmd = app.add_subcommand("eval", "Print f [1/sr] of a SOURCE (model:NAME[:key=value,...], FILE.h5, MERL, RGL .bsdf, SCATMECH) at direction pairs");
  cmd->add_option("source", opts->source, "model:NAME[:key=value,...], e.g. model:ggx:alpha=0.2,f0=0.04")->required();
  cmd->add_option("--at", opts->at, "CSV with header theta_i,phi_i,theta_r,phi_r, sza,vza,raa (raa 0: the sun's side), sza,saa,vza,vaa or SCATMECH's thetai,thetas,phis[,rotation] (degrees; negative theta = opposite azimuth)")->required();
  cmd->add_flag("--radians", opts->radians, "Angles in PAIRS.csv are in radians");
  cmd->add_flag("--strict", opts->strict, "Negative f (non-physical) is an error, not a warning");
  cmd->callback([opts] { run_eval(*opts); });
}

const CommandRegistrar kCmdEvalRegistrar("eval", add_eval_command);

}  // namespace
}  // namespace icobrdf::cli
