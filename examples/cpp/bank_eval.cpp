// Read a bank (or spectrum file) and sample reflected directions from each material, as a renderer would.
//   bank_eval BANK.h5
// Each material opens as a SOURCE "BANK.h5#NAME", whatever its representation (modes, half-angle lobe,
// hybrid). A MaterialSampler draws directions for w_i at 40 degrees with pdf [1/sr] and weights f cos / pdf;
// the mean weight estimates the directional albedo (white furnace), printed next to the grid's own sum.
#include <cmath>
#include <cstdio>
#include <random>

#include "icobrdf/core/basis/direction.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/material_sampler.hpp"

int main(int argc, char** argv) {
  using namespace icobrdf;
  if (argc != 2) return std::fprintf(stderr, "usage: bank_eval BANK.h5\n"), 2;
  const BankContents bank = read_bank(argv[1], ReadOptions{.read_luts = false});  // metadata and spectra, no LUTs
  const Eigen::Vector3d wi = direction_from_angles(40 * M_PI / 180, 0.0);
  constexpr int kDraws = 100000;
  std::mt19937_64 rng(1);  // fixed seed: the output is reproducible
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::VectorXd u1(kDraws), u2(kDraws);
  for (int i = 0; i < kDraws; ++i) u1[i] = uniform(rng), u2[i] = uniform(rng);
  for (const auto& m : bank.materials) {
    const MaterialSampler sampler(open_source(std::string(argv[1]) + "#" + m.name), 4);  // level 4: 2,592 cells
    const IncidentDistribution dist = sampler.distribution(wi);  // reuse it for every draw at this w_i
    const MaterialSamples s = sampler.sample(dist, u1, u2);
    const Eigen::Vector3d mirror(-wi.x(), -wi.y(), wi.z());
    int near_mirror = 0;  // draws within 15 degrees of the mirror direction
    Eigen::VectorXd albedo = Eigen::VectorXd::Zero(s.weight.cols());  // per channel: the mean weight
    for (int i = 0; i < kDraws; ++i) {
      near_mirror += s.directions.row(i).dot(mirror) > std::cos(15 * M_PI / 180);
      albedo += s.weight.row(i).transpose() / kDraws;
    }
    std::printf("%-20s %-10s albedo(40 deg): sampled", m.name.c_str(), representation_name(m).c_str());
    for (Eigen::Index c = 0; c < s.weight.cols(); ++c) std::printf(" %.4f", albedo[c]);
    std::printf(", grid sum (channel mean) %.4f; %.1f%% of draws within 15 deg of the mirror; pdf there %.3g 1/sr\n", dist.albedo_estimate,
                100.0 * near_mirror / kDraws, sampler.directions().pdf(dist.cells, mirror));
  }
  return 0;
}
