#include "icobrdf/lab/measured_benchmark.hpp"

#include <fmt/core.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <tuple>
#include <sstream>

#include "icobrdf/core/fit/half_angle_fit.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/scramble.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/brdf_source.hpp"
#include "icobrdf/io/material_eval.hpp"
#include "icobrdf/io/scene.hpp"
#include "icobrdf/lab/nbrdf_network.hpp"
#include "icobrdf/pipeline/bank_builder.hpp"
#include "icobrdf/pipeline/bank_resume.hpp"
#include "icobrdf/pipeline/held_out.hpp"
#include "icobrdf/pipeline/lobe_budget.hpp"
#include "icobrdf/pipeline/memo_source.hpp"
#include "icobrdf/plot/line_chart.hpp"

namespace icobrdf::lab {
namespace {

namespace fs = std::filesystem;

// Smallest number of test pairs: below it the error's own sampling spread (~1/sqrt(pairs) of the glossy
// peaks' share) exceeds the differences the report compares.
constexpr int kMinPairs = 100;
// Grids of the small lobes: the bank's budget grids (icobrdf/pipeline/lobe_budget.hpp); each budget takes, per
// storage, d grid and rank, the largest n_t that fits.
constexpr int kSmallLobeMaxRank = 4;
// Storage of the small lobes: factor sets per channel or shared (channel scales), and the precisions.
constexpr bool kSmallLobeShared[] = {false, true};
constexpr FactorPrecision kSmallLobePrecisions[] = {FactorPrecision::Float64, FactorPrecision::Float32, FactorPrecision::Int16,
                                                    FactorPrecision::Int8};
// Validation pairs of the small lobes' choice (their own seed): a quarter of the test pairs' count is enough
// to rank grids whose errors differ by more than a few percent.
constexpr int kValidationShare = 4;
// Validation errors closer than this share of the lowest are ties, which go to the fewest bytes: the
// validation error's own sampling spread between candidates fitted to the same data is of this order.
constexpr double kValidationTie = 0.005;

std::string stem_of(const std::string& path) { return fs::path(path).stem().string(); }

// The material's name in the scene: the file stem without the "_rgb" / "_spec" suffix.
std::string material_name(const std::string& path) {
  std::string s = stem_of(path);
  for (const char* suffix : {"_rgb", "_spec"}) {
    const std::string x(suffix);
    if (s.size() > x.size() && s.compare(s.size() - x.size(), x.size(), x) == 0) s.resize(s.size() - x.size());
  }
  return s;
}

struct TestPairs {
  RowMatrix3d wi, wr;
  Eigen::VectorXd w;   // cos(theta_i) cos(theta_r)
  Eigen::MatrixXd f, reciprocal;
};

TestPairs test_pairs(const BrdfSource& source, int n, const std::string& seed_text) {
  TestPairs t;
  uniform_pairs(n, fnv1a64(seed_text), t.wi, t.wr);
  t.w = t.wi.col(2).cwiseProduct(t.wr.col(2));
  t.f = source.eval(t.wi, t.wr);
  t.reciprocal = 0.5 * (t.f + source.eval(t.wr, t.wi));
  if (!t.f.allFinite()) throw InputError(source.spec() + ": non-finite values at test pairs, expected finite f");
  return t;
}

double relative_l2(const Eigen::VectorXd& w, const Eigen::MatrixXd& fit, const Eigen::MatrixXd& ref) {
  const double r = (w.asDiagonal() * ref).norm();
  const double d = (w.asDiagonal() * (fit - ref)).norm();
  return r > 0 ? d / r : d;
}

std::string storage_text(bool shared, FactorPrecision p) {
  return std::string(shared ? "shared " : "") + factor_precision_name(p);
}

// The small lobes of one material: per budget, the candidate with the smallest validation error among the
// storages, d grids and ranks (the factors fitted once per grid, rank and factor sets, then rounded to each
// precision and evaluated as stored).
std::vector<BudgetPoint> small_lobes(const BrdfSource& source, const TestPairs& test, const TestPairs& validation, const MeasuredBenchOptions& o,
                                     const std::string& name) {
  const int channels = source.channels();
  const MemoSource memo(source);  // the grids repeat across ranks and budgets
  // The lobes are fitted to the reciprocal part (f(a, b) + f(b, a)) / 2: a lobe is reciprocal (a node stands
  // for a pair and its swap), so the part it can hold is f_rec, and fitting f at one ordering of each node pair
  // would add the data's asymmetry at that ordering to the lobe's error against f_rec (and against f).
  const PairSampler sampler = [&memo](const RowMatrix3d& wi, const RowMatrix3d& wr, Eigen::Ref<Eigen::MatrixXd> out) {
    out = 0.5 * (memo.eval(wi, wr) + memo.eval(wr, wi));
  };
  struct Tried {
    double validation, error, error_reciprocal;
    long long bytes;
    std::string grid;
  };
  std::map<std::tuple<bool, int, int, int, int>, HalfAngleFactors> fitted;
  std::map<std::tuple<bool, int, int, int, int, int>, Tried> tried;
  const auto evaluate = [&](const HalfAngleFactors& lobe, const TestPairs& t) {
    return add_lobe(Eigen::MatrixXd::Zero(t.wi.rows(), channels), lobe, t.wi, t.wr);
  };
  std::vector<BudgetPoint> points;
  for (const long long budget : o.budgets) {
    std::vector<Tried> candidates;
    for (const bool shared : kSmallLobeShared)
      for (const FactorPrecision precision : kSmallLobePrecisions)
        for (const auto& d : kLobeBudgetD)
          for (int rank = 1; rank <= kSmallLobeMaxRank; ++rank) {
            const int n_t = largest_n_t(budget, channels, rank, d[0], d[1], shared, precision);
            if (n_t == 0) continue;
            const auto key = std::make_tuple(shared, n_t, d[0], d[1], rank, static_cast<int>(precision));
            auto it = tried.find(key);
            if (it == tried.end()) {
              const auto fkey = std::make_tuple(shared, n_t, d[0], d[1], rank);
              auto f = fitted.find(fkey);
              if (f == fitted.end()) {
                HalfAngleFitOptions fo;
                fo.quantity = kMeasuredLobeQuantity;  // as the bank builder's measured lobes
                fo.isotropic = true;
                fo.n_t = n_t;
                fo.n_theta_d = d[0];
                fo.n_phi_d = d[1];
                fo.fixed_rank = rank;
                fo.max_rank = rank;
                fo.shared_channels = shared;
                fo.max_sweeps = 60;  // as the bank builder's lobes (half_angle_representation.cpp kMaxSweeps)
                fo.sweep_tolerance = 1e-4;
                f = fitted.emplace(fkey, fit_half_angle(sampler, channels, fo).factors).first;
              }
              HalfAngleFactors lobe = f->second;  // as stored: rounded to the precision
              lobe.precision = precision;
              lobe.quantize();
              const Eigen::MatrixXd t = evaluate(lobe, test);
              Tried x{relative_l2(validation.w, evaluate(lobe, validation), validation.reciprocal), relative_l2(test.w, t, test.f),
                      relative_l2(test.w, t, test.reciprocal), static_cast<long long>(lobe.bytes()) + kLobeHeaderBytes,
                      fmt::format("{}x{}x{} rank {} {}", n_t, d[0], d[1], rank, storage_text(shared, precision))};
              it = tried.emplace(key, x).first;
            }
            candidates.push_back(it->second);
          }
    if (candidates.empty()) continue;
    // The fewest bytes among the candidates within kValidationTie of the lowest validation error.
    double lowest = INFINITY;
    for (const Tried& c : candidates) lowest = std::min(lowest, c.validation);
    std::optional<Tried> best;
    for (const Tried& c : candidates)
      if (c.validation <= lowest * (1 + kValidationTie) && (!best || c.bytes < best->bytes)) best = c;
    points.push_back({budget, best->bytes, best->grid, best->error, best->error_reciprocal});
    if (o.progress)
      o.progress(fmt::format("{}: lobe within {} B: {} ({} B), error {:.4f}, reciprocal part {:.4f}", name, budget, best->grid,
                             best->bytes, best->error, best->error_reciprocal));
  }
  return points;
}

std::string scene_text(const MeasuredBenchOptions& o, const std::vector<std::string>& names) {
  std::ostringstream s;
  s << "[bank]\nlevel = 4\nlevels = [4]\norder_max = 4\ntarget = " << fmt::format("{}", o.target)
    << "\nmetric = \"cosine\"\nsampling = \"centre\"\nstore_lut = false\nholdout_pairs = 20000\nrepresentations = [";
  for (size_t k = 0; k < o.representations.size(); ++k) s << (k ? ", " : "") << '"' << o.representations[k] << '"';
  s << "]\n";
  for (size_t k = 0; k < o.files.size(); ++k)
    s << "\n[[material]]\nname = \"" << names[k] << "\"\nsource = \"" << fs::absolute(o.files[k]).string() << "\"\n";
  return s.str();
}

// The builder's choices, all materials in one build (scene and bank in o.work_dir); the finished materials
// into `records`: the bank's, or, when a material missed its target (no bank is written then), those of the
// resume file the build kept them in.
BankBuildResult build_measured_bank(const MeasuredBenchOptions& o, const std::vector<std::string>& names, double& seconds,
                                    std::map<std::string, MaterialRecord>& records) {
  fs::create_directories(o.work_dir);
  const std::string scene_path = (fs::path(o.work_dir) / "measured-scene.toml").string();
  const std::string bank_path = (fs::path(o.work_dir) / "measured-bank.h5").string();
  std::ofstream(scene_path) << scene_text(o, names);
  const Scene scene = read_scene(scene_path);
  BankBuildOptions b;
  b.output = bank_path;
  b.progress = o.progress;
  b.materials_at_once = o.materials_at_once;
  const auto t0 = std::chrono::steady_clock::now();
  const BankBuildResult built = build_bank(scene, b);
  seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (built.written) {
    ReadOptions no_luts;
    no_luts.read_luts = false;
    BankContents bank = read_bank(bank_path, no_luts);
    for (auto& r : bank.materials) records.emplace(r.name, std::move(r));
  } else if (!built.resume_file.empty()) {
    if (auto kept = read_resume_file(built.resume_file))
      for (auto& [key, r] : *kept) records.emplace(r.name, std::move(r));
  }
  return built;
}

}  // namespace

MeasuredBench run_measured_bench(const MeasuredBenchOptions& o) {
  if (o.files.empty()) throw ArgumentError("bench measured: no RGL files given, expected at least one .bsdf file");
  if (o.pairs < kMinPairs) throw ArgumentError("bench measured: --pairs " + std::to_string(o.pairs) + ", expected >= " + std::to_string(kMinPairs));
  if (!(o.target > 0)) throw ArgumentError("bench measured: --target " + fmt::format("{}", o.target) + ", expected > 0");
  for (const long long b : o.budgets)
    if (b <= 0) throw ArgumentError("bench measured: --budgets " + std::to_string(b) + ", expected positive byte counts");
  MeasuredBench bench;
  bench.threads = omp_get_max_threads();
  bench.target = o.target;
  std::vector<std::string> names;
  for (const auto& f : o.files) names.push_back(material_name(f));
  bench.budgets = o.budgets;
  BankBuildResult built;
  std::map<std::string, MaterialRecord> records;
  if (o.bank) built = build_measured_bank(o, names, bench.bank_seconds, records);
  for (size_t k = 0; k < o.files.size(); ++k) {
    MeasuredRow row;
    row.name = names[k];
    row.file = o.files[k];
    const auto source = open_source(o.files[k]);
    const TestPairs test = test_pairs(*source, o.pairs, "measured|" + row.name);
    row.asymmetry = relative_l2(test.w, test.reciprocal, test.f);
    row.noise = noise_figure(*source, PairValues{test.wi, test.wr, test.f}, test.w);
    for (const auto& rep : built.materials)
      if (rep.name == row.name) {
        row.representation = rep.ok ? rep.representation : "failed: " + rep.error;
        row.met = rep.ok && rep.error_l2 <= o.target;
        row.bytes = rep.bytes;
      }
    const auto rec = records.find(row.name);
    if (rec != records.end()) {
      const Eigen::MatrixXd v = evaluate_material(rec->second.spectrum, rec->second.lobe, test.wi, test.wr);
      row.error = relative_l2(test.w, v, test.f);
      row.error_reciprocal = relative_l2(test.w, v, test.reciprocal);
    } else {
      row.error = row.error_reciprocal = std::numeric_limits<double>::quiet_NaN();
    }
    if (!o.nbrdf_dir.empty()) {
      const fs::path net = fs::path(o.nbrdf_dir) / (stem_of(o.files[k]) + ".h5");
      if (fs::exists(net)) {
        const Eigen::MatrixXd n = read_nbrdf_network(net.string()).eval(test.wi, test.wr);
        row.has_nbrdf = true;
        row.nbrdf_error = relative_l2(test.w, n, test.f);
        row.nbrdf_error_reciprocal = relative_l2(test.w, n, test.reciprocal);
      }
    }
    if (o.small_lobes) {
      const auto s0 = std::chrono::steady_clock::now();
      const TestPairs validation = test_pairs(*source, std::max(kMinPairs, o.pairs / kValidationShare), "measured-validation|" + row.name);
      row.budgets = small_lobes(*source, test, validation, o, row.name);
      row.small_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
    }
    bench.rows.push_back(std::move(row));
  }
  return bench;
}

std::string measured_bench_markdown(const MeasuredBench& b) {
  std::ostringstream s;
  s << fmt::format("Bank of {} material(s), target {} (cosine metric), built in {:.1f} s on {} thread(s).\n\n", b.rows.size(), b.target,
                   b.bank_seconds, b.threads);
  s << "Errors: cosine-weighted relative L2 on test pairs no fit saw, against the data f and against its reciprocal part "
       "(f(a,b) + f(b,a))/2; asymmetry = |w (f - f_rec)| / |w f|; noise = |w sigma| / |w f|, sigma the noise along the "
       "file's own tables (docs/measured.md).\n\n";
  s << "| material | asymmetry | noise | bank: representation | bytes | error | vs reciprocal | NBRDF 2,700 B: error | vs reciprocal | "
       "lobe <= 2,700 B: grid | bytes | error | vs reciprocal |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  const auto num = [](double x) { return std::isfinite(x) ? fmt::format("{:.4f}", x) : std::string("-"); };
  for (const auto& r : b.rows) {
    const BudgetPoint* p = nullptr;
    for (const auto& q : r.budgets)
      if (q.budget == 2700) p = &q;
    s << fmt::format("| {} | {} | {} | {}{} | {} | {} | {} | {} | {} | {} | {} | {} | {} |\n", r.name, num(r.asymmetry), num(r.noise), r.representation,
                     r.met ? "" : " (target missed)", r.bytes, num(r.error), num(r.error_reciprocal),
                     r.has_nbrdf ? num(r.nbrdf_error) : "-", r.has_nbrdf ? num(r.nbrdf_error_reciprocal) : "-", p ? p->grid : "-",
                     p ? std::to_string(p->bytes) : "-", p ? num(p->error) : "-", p ? num(p->error_reciprocal) : "-");
  }
  s << "\nSmall lobes (error against the reciprocal part) by byte budget:\n\n| material |";
  for (const long long k : b.budgets) s << " <= " << k << " B |";
  s << " seconds |\n|---|";
  for (size_t k = 0; k < b.budgets.size(); ++k) s << "---|";
  s << "---|\n";
  for (const auto& r : b.rows) {
    s << "| " << r.name << " |";
    for (const long long k : b.budgets) {
      std::string cell = "-";
      for (const auto& q : r.budgets)
        if (q.budget == k) cell = fmt::format("{:.4f} ({})", q.error_reciprocal, q.grid);
      s << " " << cell << " |";
    }
    s << fmt::format(" {:.1f} |\n", r.small_seconds);
  }
  return s.str();
}

void plot_measured_bench(const MeasuredBench& b, const std::string& png_path) {
  std::vector<plot::Series> series;
  plot::Series nbrdf{"NBRDF (2,700 B)", {}, {}};
  nbrdf.line = false;
  nbrdf.marker = plot::Marker::Cross;
  nbrdf.colour = {0, 0, 0};
  int index = 0;
  for (const auto& r : b.rows) {
    plot::Series s{r.name, {}, {}};
    s.colour = plot::series_colour(index++);
    for (const auto& q : r.budgets) {
      s.x.push_back(static_cast<double>(q.bytes));
      s.y.push_back(q.error_reciprocal);
    }
    series.push_back(s);
    if (r.has_nbrdf) {
      nbrdf.x.push_back(2700.0);
      nbrdf.y.push_back(r.nbrdf_error_reciprocal);
    }
  }
  if (!nbrdf.x.empty()) series.push_back(nbrdf);
  plot::ChartOptions o;
  o.title = "Measured materials: error against bytes";
  o.x_label = "bytes per material";
  o.y_label = "relative L2 vs reciprocal part (cosine)";
  o.log_x = o.log_y = true;
  o.width = 860;
  o.note = "lines: isotropic half-angle lobes chosen per budget; crosses: NBRDF networks";
  plot::draw_line_chart(series, o, png_path);
}

namespace {
namespace fs = std::filesystem;
}  // namespace

std::vector<std::string> bsdf_files(const std::vector<std::string>& inputs) {
  std::vector<std::string> out;
  for (const auto& in : inputs) {
    std::error_code ec;
    if (fs::is_directory(in, ec)) {
      std::vector<std::string> found;
      for (const auto& e : fs::directory_iterator(in))
        if (e.path().extension() == ".bsdf") found.push_back(e.path().string());
      if (found.empty()) throw InputError(in + ": no .bsdf file in the folder, expected RGL material files");
      std::sort(found.begin(), found.end());
      out.insert(out.end(), found.begin(), found.end());
    } else if (fs::is_regular_file(in, ec)) {
      out.push_back(in);
    } else {
      throw InputError(in + ": no such file or folder, expected an RGL .bsdf file or a folder of them");
    }
  }
  return out;
}

std::string write_measured_report(const MeasuredBench& b, const std::string& dir_text) {
  const fs::path dir(dir_text);
  plot_measured_bench(b, (dir / "error-vs-bytes.png").string());
  const std::string md = "# bench measured\n\n" + measured_bench_markdown(b) + "\n![error against bytes](error-vs-bytes.png)\n";
  std::ofstream out(dir / "report.md", std::ios::binary);
  out << md;
  out.close();
  if (!out) throw IoError("--report " + dir_text + ": cannot write report.md");
  return md;
}

}  // namespace icobrdf::lab
