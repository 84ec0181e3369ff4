#pragma once
// The report of `icobrdf bench project`: one projection C = P^T F P of a cells x cells LUT timed with the
// library's call and with raw OpenBLAS in the same process (icobrdf/lab/projection_benchmark.hpp), with the
// ratio to the machine's measured FP64 peak (icobrdf/lab/machine.hpp) next to the nominal one, the memory floor
// of streaming F once at the measured bandwidth, and the ratio to the BLAS baseline twice: OpenBLAS as this
// process loaded it, and OpenBLAS on the kernel it picks for the CPU, timed in a child process whose
// environment lacks kBlasOverrides and, when that kernel is narrower than the CPU's widest vectors (a CPU
// newer than the OpenBLAS build), again with OPENBLAS_CORETYPE naming the widest kernel: the faster is the
// baseline. The parent's environment is not changed. A child that fails is reported, not fatal (old OpenBLAS
// builds can crash without those variables on some CPUs).
//
// GFLOP/s count the general product's flops (comparable with BLAS); the peak ratio counts the flops the
// library's call performs (about half for a symmetric F).
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace icobrdf::lab {

// The variables OpenBLAS reads at load time to override its own choice of kernel and cache size.
inline const std::vector<std::string> kBlasOverrides = {"OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE"};

struct ProjectionRequest {
  int level = 5, order = 8, threads = 1, repeat = 5;
  bool symmetric = false;
  double peak_gflops = 0.0;  // > 0: the FP64 peak the ratio uses; 0: measured
  std::string peak_given_by;  // the report's peak_source when peak_gflops > 0 (what gave it)
  // The command line of a child that times OpenBLAS alone at the same sizes and prints blas_only_report's
  // JSON on one line; empty: no child (blas_best is null).
  std::vector<std::string> blas_child;
};

// The child's side: raw OpenBLAS alone (measure_blas_projection) as JSON, with its coefficients.
nlohmann::json blas_only_report(int level, int order, int threads, int repeat, bool symmetric);

// The parent's side, as JSON: level, order, cells, symmetric, modes, threads, seconds, gflops, peak_gflops,
// peak_ratio, performed_gflops, peak_source, measured_peak_gflops, nominal_peak_gflops, fma_chains_per_thread,
// simd_target, bandwidth_gbs, stream_seconds, stream_ratio, lut_huge_page_fraction, blas_seconds, blas_ratio,
// blas_gflops, cpu_seconds, blas_cpu_seconds, blas_cpu_ratio, blas_core, blas_config, flops_per_cycle_per_core,
// cpu_mhz, relative_difference_to_blas, blas, blas_seconds_fp_first, blas_seconds_pf_first, blas_best (the
// child's run: seconds, gflops, ratio, cpu_ratio, core, environment, relative_difference, and "other" when a
// second kernel was timed; or {"error": ...}), eigen_simd, cpu_model, load_before, load_after.
nlohmann::json projection_report(const ProjectionRequest& request);
// The text report of projection_report's JSON: the sizes, the machine (peak, bandwidth, huge pages), icobrdf's and
// OpenBLAS's times and their ratio, and OpenBLAS on its own best kernel.
std::string projection_report_text(const nlohmann::json& report);

}  // namespace icobrdf::lab
