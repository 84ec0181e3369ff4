// Read a bank (or spectrum file) and evaluate every material at one direction pair.
//   bank_eval BANK.h5
// Each material opens as a SOURCE "BANK.h5#NAME", whatever its representation (modes, half-angle lobe,
// hybrid); eval returns f [1/sr] per channel.
#include <cmath>
#include <cstdio>

#include "icobrdf/core/direction.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/brdf_source.hpp"

int main(int argc, char** argv) {
  using namespace icobrdf;
  if (argc != 2) return std::fprintf(stderr, "usage: bank_eval BANK.h5\n"), 2;
  const BankContents bank = read_bank(argv[1], ReadOptions{.read_luts = false});  // metadata and spectra, no LUTs
  RowMatrix3d wi(1, 3), wr(1, 3);
  wi.row(0) = direction_from_angles(40 * M_PI / 180, 0.0).transpose();
  wr.row(0) = direction_from_angles(40 * M_PI / 180, M_PI).transpose();
  for (const auto& m : bank.materials) {
    const auto source = open_source(std::string(argv[1]) + "#" + m.name);
    const Eigen::MatrixXd f = source->eval(wi, wr);  // 1 x channels
    std::printf("%-20s %-10s f(40 deg, mirror) =", m.name.c_str(), representation_name(m).c_str());
    for (Eigen::Index c = 0; c < f.cols(); ++c) std::printf(" %.5g", f(0, c));
    std::printf(" 1/sr\n");
  }
  return 0;
}
