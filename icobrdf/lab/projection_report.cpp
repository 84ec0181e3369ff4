#include "icobrdf/lab/projection_report.hpp"

#include <fmt/core.h>

#include <string>

#include <Eigen/Core>
#include <stdexcept>

#include "icobrdf/blas/blas_dense_kernels.hpp"
#include "icobrdf/lab/child_process.hpp"
#include "icobrdf/lab/machine.hpp"
#include "icobrdf/lab/projection_benchmark.hpp"

namespace icobrdf::lab {
namespace {

nlohmann::json matrix_json(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    std::vector<double> row(static_cast<size_t>(m.cols()));
    for (Eigen::Index j = 0; j < m.cols(); ++j) row[static_cast<size_t>(j)] = m(i, j);
    rows.push_back(row);
  }
  return rows;
}

Eigen::MatrixXd matrix_of(const nlohmann::json& rows, Eigen::Index n) {
  Eigen::MatrixXd m(n, n);
  if (!rows.is_array() || static_cast<Eigen::Index>(rows.size()) != n) throw std::runtime_error("coefficients are not " + std::to_string(n) + " rows");
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto& row = rows[static_cast<size_t>(i)];
    if (!row.is_array() || static_cast<Eigen::Index>(row.size()) != n) throw std::runtime_error("a coefficient row is not " + std::to_string(n) + " long");
    for (Eigen::Index j = 0; j < n; ++j) m(i, j) = row[static_cast<size_t>(j)].get<double>();
  }
  return m;
}

// One child run without the OpenBLAS overrides and with `added` set. Returns the JSON the report carries:
// seconds, core, agreement with our C; or {"error": ...}.
nlohmann::json blas_child(const ProjectionRequest& q, const ProjectionBenchmark& ours, const std::vector<std::string>& added,
                          const std::string& environment) {
  const ChildResult r = run_child(q.blas_child, kBlasOverrides, added);
  if (r.signal != 0) return {{"error", fmt::format("the OpenBLAS run {} was killed by signal {}", environment, r.signal)}};
  if (r.exit_code != 0)
    return {{"error", fmt::format("the OpenBLAS run {} exited with {}: {}", environment, r.exit_code, r.err.substr(0, r.err.find('\n')))}};
  try {
    const auto c = nlohmann::json::parse(r.out);
    const Eigen::MatrixXd coefficients = matrix_of(c.at("coefficients"), ours.modes);
    const double seconds = c.at("blas_seconds").get<double>();
    return {{"seconds", seconds},
            {"seconds_fp_first", c.at("blas_seconds_fp_first")},
            {"seconds_pf_first", c.at("blas_seconds_pf_first")},
            {"gflops", ours.flops / seconds / 1e9},
            {"ratio", seconds / ours.seconds},
            {"cpu_seconds", c.at("blas_cpu_seconds")},
            {"cpu_ratio", c.at("blas_cpu_seconds").get<double>() / ours.cpu_seconds},
            {"core", c.at("blas_core")},
            {"config", c.at("blas_config")},
            {"relative_difference", relative_difference(ours.coefficients, coefficients)},
            {"environment", environment}};
  } catch (const std::exception& e) {
    return {{"error", fmt::format("the OpenBLAS run {} printed no readable result: {}", environment, e.what())}};
  }
}

// OpenBLAS at its best: a child on the kernel OpenBLAS picks itself; when that kernel is narrower than the
// CPU's widest vectors, a second child with OPENBLAS_CORETYPE naming the widest kernel. The faster successful
// run is the baseline; the other is kept under "other" so that both are reported.
nlohmann::json best_blas(const ProjectionRequest& q, const ProjectionBenchmark& ours) {
  nlohmann::json own = blas_child(q, ours, {}, "without OPENBLAS_CORETYPE and OPENBLAS_L2_SIZE");
  const BlasKernel widest = widest_blas_kernel_for_cpu();
  if (own.contains("error") || widest.core.empty() || blas_kernel_vector_bits(own.at("core").get<std::string>()) >= widest.vector_bits)
    return own;
  nlohmann::json forced = blas_child(q, ours, {"OPENBLAS_CORETYPE=" + widest.core}, "with OPENBLAS_CORETYPE=" + widest.core);
  if (forced.contains("error") || forced.at("seconds").get<double>() >= own.at("seconds").get<double>()) {
    own["other"] = forced;
    return own;
  }
  forced["other"] = own;
  return forced;
}

}  // namespace

nlohmann::json blas_only_report(int level, int order, int threads, int repeat, bool symmetric) {
  const BlasProjection b = measure_blas_projection(level, order, threads, repeat, symmetric);
  return {{"blas_seconds", b.seconds},         {"blas_cpu_seconds", b.cpu_seconds},         {"blas_seconds_fp_first", b.seconds_fp_first},
          {"blas_seconds_pf_first", b.seconds_pf_first}, {"blas_core", b.core},
          {"blas_config", b.config},           {"coefficients", matrix_json(b.coefficients)}};
}

nlohmann::json projection_report(const ProjectionRequest& q) {
  const std::string load_before = load_average();
  const ProjectionBenchmark b = measure_projection(q.level, q.order, q.threads, q.repeat, q.symmetric);
  const double measured_peak = q.peak_gflops > 0 ? 0.0 : measure_fp64_peak_gflops(q.threads);
  const double bandwidth = measure_bandwidth_gbs(q.threads);
  const nlohmann::json best = q.blas_child.empty() ? nlohmann::json(nullptr) : best_blas(q, b);
  const double ours = b.seconds, blas = b.blas.seconds;
  const double performed_gflops = b.performed_flops / ours / 1e9;  // what the peak ratio uses
  const double peak = q.peak_gflops > 0 ? q.peak_gflops : measured_peak;
  const double lut_bytes = 8.0 * static_cast<double>(b.cells) * static_cast<double>(b.cells);
  const double stream_seconds = lut_bytes / (bandwidth * 1e9);  // F read once: the memory floor of the projection
  return {{"level", q.level},      {"order", q.order},          {"cells", b.cells},  {"symmetric", q.symmetric},
          {"modes", b.modes},      {"threads", q.threads},      {"seconds", ours},
          {"gflops", b.flops / ours / 1e9},  {"peak_gflops", peak}, {"peak_ratio", peak > 0 ? performed_gflops / peak : 0.0},
          {"performed_gflops", performed_gflops},
          {"peak_source", q.peak_gflops > 0 ? q.peak_given_by : std::string("measured")},
          {"measured_peak_gflops", measured_peak}, {"nominal_peak_gflops", fp64_peak_gflops(q.threads)},
          {"fma_chains_per_thread", kFmaChains}, {"simd_target", simd_target_description()},
          {"bandwidth_gbs", bandwidth}, {"stream_seconds", stream_seconds}, {"stream_ratio", stream_seconds / ours},
          {"lut_huge_page_fraction", b.lut_huge_page_fraction},
          {"blas_seconds", blas},  {"blas_ratio", blas / ours}, {"blas_gflops", b.flops / blas / 1e9},
          {"cpu_seconds", b.cpu_seconds}, {"blas_cpu_seconds", b.blas.cpu_seconds}, {"blas_cpu_ratio", b.blas.cpu_seconds / b.cpu_seconds},
          {"blas_core", b.blas.core}, {"blas_config", b.blas.config},
          {"flops_per_cycle_per_core", flops_per_cycle_per_core()}, {"cpu_mhz", cpu_mhz()},
          {"relative_difference_to_blas", b.relative_difference_to_blas}, {"blas", "OpenBLAS (cblas_dgemm), faster of (F P) and (P^T F) first"},
          {"blas_seconds_fp_first", b.blas.seconds_fp_first}, {"blas_seconds_pf_first", b.blas.seconds_pf_first},
          {"blas_best", best},
          {"eigen_simd", Eigen::SimdInstructionSetsInUse()}, {"cpu_model", cpu_model()},
          {"load_before", load_before}, {"load_after", load_average()}};
}

namespace {

// The child's run on the kernel OpenBLAS picks (and the other kernel's, when one was timed).
std::string best_blas_text(const nlohmann::json& best) {
  if (best.is_null()) return "";
  if (best.contains("error")) return "  OpenBLAS at its best: not measured (" + best["error"].get<std::string>() + ")\n";
  const auto line = [](const char* what, const nlohmann::json& r) {
    if (r.contains("error")) return fmt::format("  {}: not measured ({})\n", what, r["error"].get<std::string>());
    return fmt::format("  {} ({}, child {}): {:.4f} s ({:.4f} s CPU), {:.1f} GFLOP/s; icobrdf is {:.2f}x its speed ({:.2f}x in CPU time; "
                       "results agree to {:.1e})\n",
                       what, r["core"].get<std::string>(), r["environment"].get<std::string>(), r["seconds"].get<double>(),
                       r["cpu_seconds"].get<double>(), r["gflops"].get<double>(), r["ratio"].get<double>(), r["cpu_ratio"].get<double>(),
                       r["relative_difference"].get<double>());
  };
  std::string out = line("OpenBLAS at its best", best);
  if (best.contains("other")) out += line("OpenBLAS, the other kernel", best["other"]);
  return out;
}

}  // namespace

std::string projection_report_text(const nlohmann::json& j) {
  const auto d = [&j](const char* key) { return j.at(key).get<double>(); };
  const auto t = [&j](const char* key) { return j.at(key).get<std::string>(); };
  const double cells = d("cells"), lut_bytes = 8.0 * cells * cells;
  return fmt::format("projection C = P^T F P, level {} ({} cells), order {} ({} modes), {} thread(s){}\n", j.at("level").get<int>(),
                           j.at("cells").get<long>(), j.at("order").get<int>(), j.at("modes").get<long>(), j.at("threads").get<int>(),
                           j.at("symmetric").get<bool>() ? ", symmetric F (icobrdf reads half of it; OpenBLAS does the general product)" : "")
         + fmt::format("  machine: {}; kernels on {}; load {} before, {} after\n", t("cpu_model"), t("simd_target"), t("load_before"),
                           t("load_after"))
         + fmt::format("  FP64 peak: {:.1f} GFLOP/s {}; nominal {:.1f} ({:.0f} MHz x {} flops/cycle x cores)\n", d("peak_gflops"),
                           t("peak_source") == "measured" ? "measured (FMA throughput on all threads)" : "(" + t("peak_source") + ")",
                           d("nominal_peak_gflops"), d("cpu_mhz"), j.at("flops_per_cycle_per_core").get<int>())
         + fmt::format("  memory: {:.1f} GB/s (triad); reading F once ({:.0f} MB) takes {:.4f} s; {:.0f}% of F in huge pages\n",
                           d("bandwidth_gbs"), lut_bytes / 1e6, d("stream_seconds"), 100 * d("lut_huge_page_fraction"))
         + fmt::format("  icobrdf:                {:.4f} s ({:.4f} s CPU), {:.1f} GFLOP/s = {:.0f}% of the FP64 peak\n", d("seconds"),
                           d("cpu_seconds"), d("gflops"), 100 * d("performed_gflops") / d("peak_gflops"))
         + fmt::format("  OpenBLAS ({}): {:.4f} s ({:.4f} s CPU), {:.1f} GFLOP/s; icobrdf is {:.2f}x its speed ({:.2f}x in CPU time; results "
                           "agree to {:.1e})\n",
                           t("blas_core"), d("blas_seconds"), d("blas_cpu_seconds"), d("blas_gflops"), d("blas_ratio"), d("blas_cpu_ratio"),
                           d("relative_difference_to_blas")) +
         best_blas_text(j.at("blas_best"));
}

}  // namespace icobrdf::lab
