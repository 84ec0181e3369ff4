// What a finished material costs to send in the MPI bank build (icobrdf/cluster/distributed_bank.hpp): the
// binary wire form it sends (record_wire, made and read back), against a one-material bank image
// (bank_image, read_bank_image: what it sent before), and the final write of 1,000 records. The
// record: an order-N spectrum (full modes x modes matrix per channel, as with prune = false), C channels,
// the figures and labels a bank build stores, no LUT. Counter "bytes": the image's size.
// Results: benchmarks/RESULTS.md, section "MPI bank build"; the cost model in docs/cluster.md uses them.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "icobrdf/core/basis/hemisphere_basis.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/record_wire.hpp"

namespace {

icobrdf::BankContents one_material(int order, int channels) {
  icobrdf::MaterialRecord m;
  m.name = "m00001";
  auto& s = m.spectrum;
  s.order = order;
  s.source = "model:ggx:alpha=0.5";
  s.filter = "none";
  s.level = 3;
  s.grid_kind = "equal-area";
  s.isotropic = false;
  s.gram_error = 1e-13;
  s.max_albedo = 0.9;
  const int n = icobrdf::hemisphere_basis_count(order);
  for (int c = 0; c < channels; ++c) {
    Eigen::MatrixXd a(n, n);
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) a(i, j) = std::sin(1.0 + i + 0.37 * j + 2.1 * c) / (1 + i + j);
    s.channels.push_back(a);
  }
  m.figures = {{"target", 0.01}, {"error_l2", 0.004}, {"error_max", 0.02}, {"kept_coefficients", n * n},
               {"total_coefficients", n * n}, {"bytes", 8.0 * n * n}, {"seconds", 0.0026}, {"fit_level", 3}};
  m.labels = {{"key", "0123456789abcdef"}, {"error_measured", "yes"}};
  icobrdf::BankContents b;
  b.materials.push_back(std::move(m));
  return b;
}

void BM_BankImage(benchmark::State& state) {
  const auto b = one_material(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::string image = icobrdf::bank_image(b, "record");
    bytes = image.size();
    benchmark::DoNotOptimize(image.data());
  }
  state.counters["bytes"] = static_cast<double>(bytes);
}

void BM_ReadBankImage(benchmark::State& state) {
  const std::string image = icobrdf::bank_image(one_material(static_cast<int>(state.range(0)), static_cast<int>(state.range(1))), "record");
  for (auto _ : state) {
    auto b = icobrdf::read_bank_image(image, "record");
    benchmark::DoNotOptimize(b.materials.data());
  }
  state.counters["bytes"] = static_cast<double>(image.size());
}

// The same record through the binary wire form the MPI bank build sends (icobrdf/io/record_wire.hpp): made
// and read back.
void BM_RecordWire(benchmark::State& state) {
  const auto b = one_material(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  std::size_t bytes = 0;
  for (auto _ : state) {
    const std::string wire = icobrdf::record_wire(b.materials.front());
    bytes = wire.size();
    auto back = icobrdf::read_record_wire(wire, "record");
    benchmark::DoNotOptimize(back.spectrum.channels.data());
  }
  state.counters["bytes"] = static_cast<double>(bytes);
}

// The final write of a bank build: `state.range(0)` order-6, 1-channel materials written to one file in
// /dev/shm (write_bank: HDF5, deflate, atomic rename), without the grid and operators.
void BM_WriteBank(benchmark::State& state) {
  const auto one = one_material(6, 1);
  icobrdf::BankContents b;
  for (int i = 0; i < state.range(0); ++i) {
    b.materials.push_back(one.materials.front());
    b.materials.back().name = "m" + std::to_string(100000 + i);
  }
  const std::string path = "/dev/shm/icobrdf-bench-write-bank-" + std::to_string(::getpid()) + ".h5";
  for (auto _ : state) icobrdf::write_bank(path, b);
  std::remove(path.c_str());
  state.counters["per_material_us"] = benchmark::Counter(static_cast<double>(state.range(0)) * 1e-6,
                                                          benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK(BM_WriteBank)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_RecordWire)->Args({6, 1})->Args({6, 3})->Args({16, 3})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BankImage)->Args({6, 1})->Args({6, 3})->Args({16, 3})->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReadBankImage)->Args({6, 1})->Args({6, 3})->Args({16, 3})->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
