// icobrdf sample: importance-sampled reflected directions of a SOURCE (icobrdf/io/material_sampler.hpp).
//   icobrdf sample SOURCE --theta-i DEG [--phi-i DEG] -n N [--seed S] [--level L] [--cell-value centre|average] [--strict]
// Output: CSV with header theta_r,phi_r,pdf,weight (weight_r,weight_g,weight_b ... per channel, named like
// eval's columns), one line per draw: angles in degrees, pdf in 1/sr (piecewise constant over the equal-area
// cells of the level), weight = f cos(theta_r) / pdf. The uniform numbers come from a 64-bit Mersenne twister
// seeded with --seed, so a run is reproducible. Nothing is printed unless every draw succeeded (an all-zero
// or non-finite row of the SOURCE is refused with exit 4 and one line); negative f is reported as
// non-physical (icobrdf/pipeline/reflectance_check.hpp; error with --strict) and sampled as 0.
#include <fmt/core.h>

#include <iostream>
#include <memory>
#include <string>

#include "cli/commands.hpp"
#include "cli/option_checks.hpp"
#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/material_sampler.hpp"
#include "icobrdf/io/sample_draws.hpp"
#include "icobrdf/pipeline/reflectance_check.hpp"
#include "icobrdf/pipeline/resource_estimate.hpp"

namespace icobrdf::cli {

namespace {

// More draws than this in one run print gigabytes of CSV (memory stays bounded: sample_draws.hpp); a
// renderer calls the library instead.
constexpr long long kMaxDraws = 100'000'000;

struct SampleOptions {
  std::string source;
  double theta_i = 0, phi_i = 0;
  long long n = 0;
  unsigned long long seed = 1;
  int level = kDefaultSamplingLevel;
  std::string cell_value = "centre";
  bool strict = false;
};

void run_sample(const SampleOptions& o) {
  const auto mode = lut_sampling_named(o.cell_value);
  if (!mode) throw ArgumentError("--cell-value: expected 'centre' or 'average', found '" + quoted_text(o.cell_value) + "'");
  std::shared_ptr<const BrdfSource> source = open_source(o.source);
  require_sampling_memory(o.level, *mode == LutSampling::CellAverage, source->channels(), "sampling " + o.source);
  const MaterialSampler sampler(std::move(source), o.level, *mode);
  const Eigen::Vector3d wi = direction_from_angles(o.theta_i * M_PI / 180, o.phi_i * M_PI / 180);
  check_sampled_reflectance(sampler, wi, {o.strict, &std::cerr});
  write_material_samples_csv(std::cout, sampler, wi, o.n, o.seed);  // a failed stream is reported at the end (main)
}

void add_sample_command(CLI::App& app) {
  auto opts = std::make_shared<SampleOptions>();
  auto* cmd = app.add_subcommand("sample", "Print importance-sampled reflected directions of a SOURCE for one incident direction (CSV: angles, pdf, weight f cos / pdf)");
  cmd->add_option("source", opts->source, "model:NAME[:key=value,...], FILE.h5[#MATERIAL], MERL, RGL .bsdf, ...")->required();
  cmd->add_option("--theta-i", opts->theta_i, "Incident polar angle [deg]")->required()->check(finite_in(0.0, 90.0));
  cmd->add_option("--phi-i", opts->phi_i, "Incident azimuth [deg]")->check(finite_in(-360.0, 360.0));
  cmd->add_option("-n", opts->n, "Number of draws")->required()->check(CLI::Range(1LL, kMaxDraws));
  cmd->add_option("--seed", opts->seed, "Seed of the uniform numbers (64-bit Mersenne twister)");
  cmd->add_option("--level", opts->level, "Equal-area grid level of the sampling density (cells of 1.4 deg at 5)")->check(CLI::Range(0, 8));
  cmd->add_option("--cell-value", opts->cell_value, "Cell masses from f at each cell's direction ('centre') or the cell's cubature ('average')");
  cmd->add_flag("--strict", opts->strict, "Negative f (non-physical) is an error, not a warning");
  cmd->callback([opts] { run_sample(*opts); });
}

const CommandRegistrar kCmdSampleRegistrar("sample", add_sample_command);

}  // namespace
}  // namespace icobrdf::cli
