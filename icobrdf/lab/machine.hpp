#pragma once
// The machine a measurement runs on, for the ratios every benchmark reports (bench project, bench sweep,
// benchmarks/): CPU model and clock from /proc/cpuinfo, the instruction set this build was compiled for and
// the one the kernels dispatch to, the FP64 peak (nominal and measured), the memory bandwidth, the load
// average and a measured GEMM rate.
//   nominal FP64 peak [GFLOP/s] = threads x flops per cycle per core x clock [GHz], with flops per cycle per
//   core of the dispatched SIMD target = 32 for AVX-512 (two 8-wide FMA pipes), 16 for AVX2 + FMA (two 4-wide
//   FMA pipes), 4 for SSE (one 2-wide add and one multiply pipe). The clock is the first "cpu MHz" line: the nominal clock on virtual machines, which can be far
//   from what the cores sustain (issue 17: 166 GFLOP/s nominal, 271 measured on a 2-core Zen 5).
//   measured FP64 peak: FMA throughput in-process, on all the threads asked for, at the vector width the
//   kernels dispatch to (icobrdf/core/support/simd_target.hpp). Ratios to the peak use the measured one.
//   memory bandwidth: a STREAM triad a = b + s c on the threads asked for, 24 bytes per element.
// Measured figures include whatever else the machine runs: report the load average with them.
#include <string>

namespace icobrdf::lab {

// Value of the first line of `file` starting with `key` ("key : value"); "" when absent.
std::string proc_field(const std::string& file, const std::string& key);

double cpu_mhz();               // MHz; 0 when /proc/cpuinfo has no clock
std::string cpu_model();        // "unknown" when absent
int flops_per_cycle_per_core(); // FP64, of the SIMD target the kernels dispatch to
const char* compiled_isa();     // "AVX-512", "AVX2 + FMA", "AVX" or "SSE2"
double fp64_peak_gflops(int threads);  // nominal, of min(threads, processors) cores: extra threads add no peak

// Independent FMA chains per thread of the peak loop: enough to hide the FMA latency on both pipes.
constexpr int kFmaChains = 12;
// FP64 FMA throughput [GFLOP/s] of `threads` OpenMP threads, each running kFmaChains independent chains on
// vectors of the dispatched SIMD target; best of 5 runs of ~10 ms.
double measure_fp64_peak_gflops(int threads);
// Memory bandwidth [GB/s] of `threads` OpenMP threads: STREAM triad over 3 arrays of 64 MiB (far beyond the
// caches), first-touched by the threads that use them; best of 5 passes, 24 bytes per element (write-allocate
// traffic not counted, as STREAM does).
double measure_bandwidth_gbs(int threads);
// "0.52 0.61 0.70 (1, 5, 15 min)" or "unknown".
std::string load_average();

// GFLOP/s of an Eigen n x n x n product (2 n^3 flops), best of 3, with the threads already set.
double measure_gemm_gflops(int n);

// What a report says about the machine.
struct Machine {
  std::string cpu_model, isa;
  std::string simd_target;              // what the dispatched kernels run on (icobrdf/core/support/simd_target.hpp), with its FP64 lanes
  int cores = 0;
  double cpu_mhz = 0.0;
  int flops_per_cycle_per_core = 0;     // FP64, of the dispatched SIMD target
  double peak_gflops = 0.0;             // nominal: threads x flops/cycle x clock
  double measured_peak_gflops = 0.0;    // measure_fp64_peak_gflops (filled by the caller)
  double bandwidth_gbs = 0.0;           // measure_bandwidth_gbs (filled by the caller)
  double gemm_gflops = 0.0;             // measured: Eigen 1024 x 1024 x 1024 product, best of 3 (filled by the caller)
  std::string load_before, load_after;  // /proc/loadavg (load_after filled by the caller)
};

// "AVX3 (8 FP64 lanes)": the dispatched SIMD target.
std::string simd_target_description();

// The description for `threads` threads: clock and nominal peak, instruction sets, cores, load before.
Machine describe_machine(int threads);

}  // namespace icobrdf::lab
