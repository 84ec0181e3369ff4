#pragma once
// The machine a measurement runs on, for the ratios every benchmark reports (bench project, bench sweep,
// benchmarks/): CPU model and clock from /proc/cpuinfo, the instruction set this build was compiled for,
// its FP64 peak and the load average.
//   FP64 peak [GFLOP/s] = threads x flops per cycle per core x clock [GHz], with flops per cycle per core
//   = 32 for AVX-512 (two 8-wide FMA pipes), 16 for AVX2 + FMA (two 4-wide FMA pipes), 8 for AVX, 4 otherwise.
// The clock is the first "cpu MHz" line (the nominal clock on virtual machines; turbo is not counted).
#include <fstream>
#include <string>

namespace icobrdf::cli {

// Value of the first line of `file` starting with `key` ("key : value"); "" when absent.
inline std::string proc_field(const std::string& file, const std::string& key) {
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

inline double cpu_mhz() {
  const std::string v = proc_field("/proc/cpuinfo", "cpu MHz");
  return v.empty() ? 0.0 : std::stod(v);
}

inline std::string cpu_model() {
  const std::string v = proc_field("/proc/cpuinfo", "model name");
  return v.empty() ? "unknown" : v;
}

inline int flops_per_cycle_per_core() {
#if defined(__AVX512F__)
  return 32;
#elif defined(__AVX2__) && defined(__FMA__)
  return 16;
#elif defined(__AVX__)
  return 8;
#else
  return 4;
#endif
}

inline const char* compiled_isa() {
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

inline double fp64_peak_gflops(int threads) { return threads * flops_per_cycle_per_core() * cpu_mhz() / 1e3; }

// "0.52 0.61 0.70 (1, 5, 15 min)" or "unknown".
inline std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string a, b, c;
  in >> a >> b >> c;
  return a.empty() ? "unknown" : a + " " + b + " " + c + " (1, 5, 15 min)";
}

}  // namespace icobrdf::cli
