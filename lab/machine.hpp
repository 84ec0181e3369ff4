#pragma once
// The machine a measurement runs on, for the ratios every benchmark reports (bench project, bench sweep,
// benchmarks/): CPU model and clock from /proc/cpuinfo, the instruction set this build was compiled for,
// its FP64 peak, the load average and a measured GEMM rate.
//   FP64 peak [GFLOP/s] = threads x flops per cycle per core x clock [GHz], with flops per cycle per core
//   = 32 for AVX-512 (two 8-wide FMA pipes), 16 for AVX2 + FMA (two 4-wide FMA pipes), 8 for AVX, 4 otherwise.
// The clock is the first "cpu MHz" line (the nominal clock on virtual machines; turbo is not counted).
#include <string>

namespace icobrdf::lab {

// Value of the first line of `file` starting with `key` ("key : value"); "" when absent.
std::string proc_field(const std::string& file, const std::string& key);

double cpu_mhz();               // MHz; 0 when /proc/cpuinfo has no clock
std::string cpu_model();        // "unknown" when absent
int flops_per_cycle_per_core(); // FP64, of the instruction set compiled for
const char* compiled_isa();     // "AVX-512", "AVX2 + FMA", "AVX" or "SSE2"
double fp64_peak_gflops(int threads);  // of min(threads, processors) cores: extra threads add no peak
// "0.52 0.61 0.70 (1, 5, 15 min)" or "unknown".
std::string load_average();

// GFLOP/s of an Eigen n x n x n product (2 n^3 flops), best of 3, with the threads already set.
double measure_gemm_gflops(int n);

// What a report says about the machine.
struct Machine {
  std::string cpu_model, isa;
  int cores = 0;
  double cpu_mhz = 0.0;
  int flops_per_cycle_per_core = 0;     // FP64, of the instruction set compiled for
  double peak_gflops = 0.0;             // threads x flops/cycle x clock (as `bench project`)
  double gemm_gflops = 0.0;             // measured: Eigen 1024 x 1024 x 1024 product, best of 3 (filled by the caller)
  std::string load_before, load_after;  // /proc/loadavg (load_after filled by the caller)
};

// The description for `threads` threads: clock and peak, instruction sets, cores, load before.
Machine describe_machine(int threads);

}  // namespace icobrdf::lab
