#include "icobrdf/lab/machine.hpp"

#include <fmt/core.h>
#include <omp.h>

#include <Eigen/Core>
#include <algorithm>
#include <fstream>
#include <vector>

#include "icobrdf/core/support/simd_target.hpp"

#include "icobrdf/lab/timing.hpp"

namespace icobrdf::lab {

std::string proc_field(const std::string& file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) {
      auto v = line.substr(line.find(':') + 1);
      v.erase(0, v.find_first_not_of(" \t"));
      return v;
    }
  return "";
}

double cpu_mhz() {
  const std::string v = proc_field("/proc/cpuinfo", "cpu MHz");
  return v.empty() ? 0.0 : std::stod(v);
}

std::string cpu_model() {
  const std::string v = proc_field("/proc/cpuinfo", "model name");
  return v.empty() ? "unknown" : v;
}

int flops_per_cycle_per_core() {
  // Two FMA pipes of the dispatched width where the target has FMA (AVX2 and up: 4 doubles or more), else
  // one add and one multiply pipe.
  const int lanes = dispatched_f64_lanes();
  return lanes >= 4 ? 2 * 2 * lanes : 2 * lanes;
}

const char* compiled_isa() {
#if defined(__AVX512F__)
  return "AVX-512";
#elif defined(__AVX2__) && defined(__FMA__)
  return "AVX2 + FMA";
#elif defined(__AVX__)
  return "AVX";
#else
  return "SSE2";
#endif
}

double fp64_peak_gflops(int threads) { return std::min(threads, omp_get_num_procs()) * flops_per_cycle_per_core() * cpu_mhz() / 1e3; }

std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a.empty() ? "unknown" : a + " " + b + " " + c + " (1, 5, 15 min)";
}

double measure_gemm_gflops(int n) {
  Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n), b = Eigen::MatrixXd::Random(n, n), c(n, n);
  const double best = best_seconds(3, [&] { c.noalias() = a * b; });
  return 2.0 * n * n * static_cast<double>(n) / best / 1e9;
}

namespace {
// Elements per triad array: 8 Mi doubles = 64 MiB, far beyond any L3 this runs on.
constexpr long kTriadElements = long{1} << 23;
constexpr int kTriadPasses = 5;
}  // namespace

double measure_bandwidth_gbs(int threads) {
  std::vector<double> a(kTriadElements), b(kTriadElements), c(kTriadElements);
  double* __restrict pa = a.data();
  const double* __restrict pb = b.data();
  const double* __restrict pc = c.data();
#pragma omp parallel for schedule(static) num_threads(threads)
  for (long i = 0; i < kTriadElements; ++i) {  // first touch by the threads that use the pages
    a[static_cast<size_t>(i)] = 0.0;
    b[static_cast<size_t>(i)] = 1.0;
    c[static_cast<size_t>(i)] = 2.0;
  }
  const double s = 3.0;
  const double best = best_seconds(kTriadPasses, [&] {
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long i = 0; i < kTriadElements; ++i) pa[i] = pb[i] + s * pc[i];
  });
  volatile double sink = a[static_cast<size_t>(kTriadElements / 2)];
  (void)sink;
  return 24.0 * kTriadElements / best / 1e9;
}

std::string simd_target_description() {
  return fmt::format("{} ({} FP64 lanes)", dispatched_simd_target().name, dispatched_f64_lanes());
}

Machine describe_machine(int threads) {
  Machine m;
  m.cpu_model = cpu_model();
  m.cpu_mhz = cpu_mhz();
  m.cores = omp_get_num_procs();
  m.isa = fmt::format("compiled for {} (Eigen: {})", compiled_isa(), Eigen::SimdInstructionSetsInUse());
  m.simd_target = simd_target_description();
  m.flops_per_cycle_per_core = flops_per_cycle_per_core();
  m.peak_gflops = fp64_peak_gflops(threads);
  m.load_before = load_average();
  return m;
}

}  // namespace icobrdf::lab
