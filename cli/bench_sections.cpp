// icobrdf bench baselines | hard-cases: each report section of `bench sweep` run alone
// (cli/bench_section_command.hpp; the measurements are icobrdf/lab/baselines.hpp and icobrdf/lab/hard_cases.hpp).
#include "cli/bench_commands.hpp"
#include "cli/bench_section_command.hpp"
#include "icobrdf/lab/baselines.hpp"
#include "icobrdf/lab/hard_cases.hpp"

namespace icobrdf::cli {
namespace {

const BenchRegistrar kBaselines("baselines", [](CLI::App& bench) {
  section::add_section_subcommand(bench, "baselines",
                                  "Baseline grids (geodesic, lat-long, polar Gauss) and direct quadrature against the equal-area matrix path",
                                  {"1..5", "0..32", "1..3", "0..12", 6, lab::kMaxBaselineOrder}, lab::run_baselines);
});

const BenchRegistrar kHardCases("hard-cases", [](CLI::App& bench) {
  section::add_section_subcommand(bench, "hard-cases",
                                  "Numerical stability: order 128, delta BRDFs, Fresnel at grazing, dynamic range 1e4, float32 LUTs",
                                  {"3..5", "0..32", "2..3", "0..12", 6, 128}, lab::run_hard_cases);
});

}  // namespace
}  // namespace icobrdf::cli
