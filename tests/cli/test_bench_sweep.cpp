// icobrdf bench sweep: a tiny sweep (levels 1..2, orders 0..3, Lambert and Minnaert k = 2, --quick) checked
// against derived expectations, RESULTS.h5 read back with h5py (an independent reader), the PNG files,
// the report sections, and bad input leaving no output behind. No timing is asserted.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <set>

#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::run_cli;
using icobrdf::test::shell_quote;
using icobrdf::test::slurp;
using icobrdf::test::TempDir;
using nlohmann::json;

namespace ICOBRDF_UNITY_ID {

// Lambert (f = 1/pi) is a constant times K_0(w_i) K_0(w_r): in the span at every order, so every supported
// fit recovers it up to the rounding of sums over <= 168 cells (a few 1e-16 relative); 1e-12 leaves room for
// the conditioning of G (at most about 1.2 where the Gram error is within 0.1).
constexpr double kRoundingTol = 1e-12;
// Minnaert k = 2: f = 3/(2 pi) cos(ti) cos(tr). With rho^2 = 2 sin^2(theta/2) = 1 - cos(theta) and
// R_2^0(rho) = 2 rho^2 - 1, cos(theta) = (1 - R_2^0)/2 lies in the span of K_0 (constant) and K_2^0, so f is in
// the span of order 2: orders >= 2 on centre-sampled grids (B and the LUT rows sampled at the same points)
// recover it up to rounding as well.
// Orders 0 and 1 keep only the K_0 x K_0 part (K_1^{+-1} ~ rho cos(phi), rho sin(phi) are orthogonal to any
// function of theta alone): with K_0 = 1/sqrt(2 pi), a = <cos, K_0> = pi / sqrt(2 pi) and ||cos||^2 = 2 pi / 3,
// a^2 / ||cos||^2 = 3/4 and the relative L2 error is sqrt(1 - (3/4)^2) = sqrt(7)/4 = 0.6614.
constexpr double kMinnaertTruncationError = 0.66143782776614768;  // sqrt(7) / 4
// The held-out estimate of that continuous L2 ratio uses 200 random pairs (sampling error of a ratio of two
// correlated Monte Carlo norms, a few percent) and the discrete fit at orders 0, 1 is close to but not the
// continuous truncation: 0.05 absolute.
constexpr double kMonteCarloTol = 0.05;

// A rounded zero eigenvalue is O(eps ||G||) ~ 1e-15 against lambda_max ~ 1: a condition number above 1e10 is
// singular for any purpose here (supported rows have condition numbers near 1).
constexpr double kSingularCondition = 1e10;

const std::vector<std::string> kModels{"lambert", "minnaert:k=2"};

int cells_of(int level) { return 10 * (1 << (2 * level)) + (1 << (level + 1)); }  // 10 4^L + 2^(L+1)
int modes_of(int order) { return (order + 1) * (order + 2) / 2; }

bool exists(const std::string& p) {
  struct stat st{};
  return ::stat(p.c_str(), &st) == 0;
}

// Runs a Python snippet with Debian's python3 (h5py) and returns its stdout.
std::string run_python(const std::string& code, const std::string& arg) {
  TempDir t;
  const std::string script = t.file("s.py"), out = t.file("out.txt");
  std::ofstream(script) << code;
  const std::string cmd = "/usr/bin/python3 " + shell_quote(script) + " " + shell_quote(arg) + " > " + shell_quote(out) + " 2>&1";
  const int rc = std::system(cmd.c_str());
  const std::string text = slurp(out);
  EXPECT_EQ(rc, 0) << text;
  return text;
}

// Dumps RESULTS.h5 as JSON: root attributes, every table column with its unit, support, sections.
const char* kDumpH5 = R"PY(
import h5py, json, sys, math
def val(x):
    if isinstance(x, bytes): return x.decode()
    if hasattr(x, 'item'): x = x.item()
    if isinstance(x, float) and not math.isfinite(x): return None
    return x
with h5py.File(sys.argv[1], 'r') as f:
    out = {'attrs': {k: val(v) for k, v in f.attrs.items()}, 'table': {}, 'units': {}, 'support': {}, 'sections': {}}
    t = f['table']
    out['table_attrs'] = {k: val(v) for k, v in t.attrs.items()}
    for k in t:
        out['table'][k] = [[val(y) for y in x] if getattr(x, 'ndim', 0) else val(x) for x in t[k][()]]
        out['units'][k] = val(t[k].attrs['unit'])
    for k in f['support']:
        out['support'][k] = [val(x) for x in f['support'][k][()]]
    for name in f['sections']:
        g = f['sections'][name]
        out['sections'][name] = {'title': val(g.attrs['title']), 'markdown': g['markdown'][()].tobytes().decode(),
                                 'data': json.loads(g['data_json'][()].tobytes().decode())}
print(json.dumps(out))
)PY";

std::uint32_t crc32(const unsigned char* p, std::size_t n) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return c ^ 0xFFFFFFFFu;
}

std::uint32_t be32(const std::string& s, std::size_t at) {
  return (std::uint32_t(static_cast<unsigned char>(s[at])) << 24) | (std::uint32_t(static_cast<unsigned char>(s[at + 1])) << 16) |
         (std::uint32_t(static_cast<unsigned char>(s[at + 2])) << 8) | std::uint32_t(static_cast<unsigned char>(s[at + 3]));
}

// PNG structure (RFC 2083): signature, IHDR first with a correct CRC and non-zero size, IEND last.
void expect_valid_png(const std::string& path) {
  const std::string s = slurp(path);
  ASSERT_GT(s.size(), 8u + 25u + 12u) << path;
  EXPECT_EQ(s.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << path;
  EXPECT_EQ(be32(s, 8), 13u) << path;
  EXPECT_EQ(s.substr(12, 4), "IHDR") << path;
  EXPECT_GT(be32(s, 16), 0u) << path;
  EXPECT_GT(be32(s, 20), 0u) << path;
  EXPECT_EQ(be32(s, 29), crc32(reinterpret_cast<const unsigned char*>(s.data()) + 12, 17)) << path;
  EXPECT_EQ(s.substr(s.size() - 8, 4), "IEND") << path;
}

struct Sweep {
  TempDir dir;
  json j;
  json h5;
  std::string report;
  int exit_code = -1;
  std::string err;
};

const Sweep& tiny_sweep() {
  static Sweep* s = [] {
    auto* r = new Sweep;
    const auto res = run_cli({"bench", "sweep", "--quick", "-q", "--levels", "1..2", "--orders", "0..3", "--models", "lambert,minnaert:k=2",
                              "--threads", "1", "--json", "-o", r->dir.file("RESULTS.h5"), "--report", r->dir.file("report")});
    r->exit_code = res.exit_code;
    r->err = res.err;
    if (res.exit_code == 0) {
      r->j = json::parse(res.out);
      r->h5 = json::parse(run_python(kDumpH5, r->dir.file("RESULTS.h5")));
      r->report = slurp(r->dir.file("report/report.md"));
    }
    return r;
  }();
  return *s;
}

TEST(CliBenchSweep, TinySweepRowsFollowTheGridDefinitions) {
  const Sweep& s = tiny_sweep();
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const json& rows = s.j["rows"];
  ASSERT_EQ(rows.size(), 2u * 4u);  // levels 1..2 x orders 0..3
  std::size_t k = 0;
  for (int level = 1; level <= 2; ++level)
    for (int order = 0; order <= 3; ++order, ++k) {
      const json& r = rows[k];
      EXPECT_EQ(r["level"].get<int>(), level);
      EXPECT_EQ(r["order"].get<int>(), order);
      EXPECT_EQ(r["cells"].get<int>(), cells_of(level));
      EXPECT_EQ(r["modes"].get<int>(), modes_of(order));
      // B holds cells x modes doubles, P as many when built.
      EXPECT_GE(r["basis_bytes"].get<std::int64_t>(), std::int64_t{8} * cells_of(level) * modes_of(order));
      const bool supported = r["supported"].get<bool>();
      EXPECT_EQ(supported, r["gram_error"].get<double>() <= s.j["config"]["gram_tolerance"].get<double>()) << level << " " << order;
      EXPECT_EQ(r["projection_bytes"].get<std::int64_t>(), supported ? std::int64_t{8} * cells_of(level) * modes_of(order) : 0);
      EXPECT_GE(r["condition"].get<double>(), 1.0);  // lambda_max / lambda_min
      ASSERT_EQ(r["models"].size(), kModels.size());
      for (const json& m : r["models"]) {
        EXPECT_EQ(m["error_l2"].is_null(), !supported);
        EXPECT_EQ(m["project_seconds"].is_null(), !supported);
      }
    }
}

TEST(CliBenchSweep, UnsupportedPairsAreMarkedAndMatchTheSupportedOrder) {
  const Sweep& s = tiny_sweep();
  ASSERT_EQ(s.exit_code, 0) << s.err;
  // A row is supported exactly up to the level's largest supported order: the Gram matrix of order n is the
  // leading block of the one the support search builds (same cells, same sampling).
  for (const json& sup : s.j["support"]) {
    const int level = sup["level"].get<int>(), largest = sup["largest_order"].get<int>();
    EXPECT_EQ(sup["cells"].get<int>(), cells_of(level));
    for (const json& r : s.j["rows"])
      if (r["level"].get<int>() == level) {
        EXPECT_EQ(r["supported"].get<bool>(), r["order"].get<int>() <= largest) << level << " " << r["order"];
      }
  }
}

TEST(CliBenchSweep, MoreModesThanCellsIsUnsupportedAndNotFitted) {
  // Level 1 has 44 cells and order 8 has 45 modes: B (44 x 45) has rank <= 44, so G = B^T W B is singular.
  // A zero eigenvalue gives ||G - I||_2 >= 1, and ||A||_2 <= M max|a_ij|, so max|G - I| >= 1/45; the computed
  // smallest eigenvalue is zero up to rounding (~eps ||G||), so the condition number is infinite (null in
  // JSON) or above kSingularCondition. The row is marked unsupported, with these figures, and not fitted.
  TempDir t;
  const auto r = run_cli({"bench", "sweep", "--quick", "-q", "--levels", "1", "--orders", "8", "--models", "lambert", "--json", "-o",
                          t.file("r.h5"), "--report", t.file("rep")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  ASSERT_EQ(j["rows"].size(), 1u);
  const json& row = j["rows"][0];
  EXPECT_EQ(row["cells"].get<int>(), 44);
  EXPECT_EQ(row["modes"].get<int>(), 45);
  EXPECT_FALSE(row["supported"].get<bool>());
  EXPECT_GE(row["gram_error"].get<double>(), 1.0 / 45.0);
  EXPECT_TRUE(row["condition"].is_null() || row["condition"].get<double>() > kSingularCondition) << row["condition"];
  EXPECT_TRUE(row["operator_seconds"].is_null());
  EXPECT_TRUE(row["models"][0]["error_l2"].is_null());
  EXPECT_LT(j["support"][0]["largest_order"].get<int>(), 8);
  EXPECT_TRUE(j["pareto"][j["config"]["models"][0].get<std::string>()].empty());
}

TEST(CliBenchSweep, GramErrorShrinksWithTheLevelAtFixedOrder) {
  // Finer cells sample each mode at more points (4x the cells per level): the midpoint rule's error on the
  // smooth products K_a K_b falls, so max|G - I| at level 2 is below level 1 for every order >= 1
  // (order 0 is exact on both: K_0 is constant).
  const Sweep& s = tiny_sweep();
  ASSERT_EQ(s.exit_code, 0) << s.err;
  for (int order = 1; order <= 3; ++order)
    EXPECT_LT(s.j["rows"][4 + order]["gram_error"].get<double>(), s.j["rows"][order]["gram_error"].get<double>()) << order;
  for (int level = 0; level < 2; ++level) EXPECT_LT(s.j["rows"][4 * level]["gram_error"].get<double>(), kRoundingTol);
}

TEST(CliBenchSweep, ErrorsMatchWhatTheSpanOfTheBasisDecides) {
  const Sweep& s = tiny_sweep();
  ASSERT_EQ(s.exit_code, 0) << s.err;
  ASSERT_EQ(s.j["config"]["models"][0].get<std::string>().rfind("lambert", 0), 0u);
  for (const json& r : s.j["rows"]) {
    if (!r["supported"].get<bool>()) continue;
    const int order = r["order"].get<int>();
    const json& lambert = r["models"][0];
    EXPECT_LT(lambert["error_l2"].get<double>(), kRoundingTol) << r.dump();
    EXPECT_LT(lambert["error_max"].get<double>(), kRoundingTol) << r.dump();
    const json& minnaert = r["models"][1];
    if (order >= 2) {
      EXPECT_LT(minnaert["error_l2"].get<double>(), kRoundingTol) << r.dump();
      EXPECT_LT(minnaert["error_max"].get<double>(), kRoundingTol) << r.dump();
    } else {
      EXPECT_NEAR(minnaert["error_l2"].get<double>(), kMinnaertTruncationError, kMonteCarloTol) << r.dump();
    }
  }
}

TEST(CliBenchSweep, ParetoFrontHoldsExactlyTheUndominatedPairs) {
  const Sweep& s = tiny_sweep();
  ASSERT_EQ(s.exit_code, 0) << s.err;
  for (std::size_t m = 0; m < kModels.size(); ++m) {
    const std::string spec = s.j["config"]["models"][m].get<std::string>();
    struct P {
      int level, order;
      double t, e;
    };
    std::vector<P> all;
    for (const json& r : s.j["rows"])
      if (r["supported"].get<bool>())
        all.push_back({r["level"].get<int>(), r["order"].get<int>(), r["models"][m]["project_seconds"].get<double>(),
                       r["models"][m]["error_l2"].get<double>()});
    const auto dominated = [&](const P& p) {
      for (const P& q : all)
        if (q.t <= p.t && q.e <= p.e && (q.t < p.t || q.e < p.e)) return true;
      return false;
    };
    std::set<std::pair<int, int>> front;
    for (const json& p : s.j["pareto"][spec]) front.insert({p["level"].get<int>(), p["order"].get<int>()});
    ASSERT_FALSE(front.empty());
    for (const P& p : all) {
      if (front.count({p.level, p.order})) EXPECT_FALSE(dominated(p)) << spec << " L" << p.level << " N" << p.order;
      else if (!dominated(p)) {
        // Not on the front yet undominated: only allowed when it ties a front point exactly.
        bool ties = false;
        for (const P& q : all)
          if (front.count({q.level, q.order}) && q.t == p.t && q.e == p.e) ties = true;
        EXPECT_TRUE(ties) << spec << " L" << p.level << " N" << p.order;
      }
    }
  }
}

TEST(CliBenchSweep, ResultsFileAgreesWithTheJson) {
  const Sweep& s = tiny_sweep();
  ASSERT_EQ(s.exit_code, 0) << s.err;
  const json& h = s.h5;
  EXPECT_EQ(h["attrs"]["format"], "icobrdf-sweep");
  EXPECT_EQ(h["attrs"]["format_version"], "1.0");
  EXPECT_EQ(h["attrs"]["complete"], 1);
  EXPECT_EQ(h["attrs"]["held_out_pairs"], 200);  // --quick
  EXPECT_NE(h["attrs"]["command"].get<std::string>().find("bench sweep"), std::string::npos);
  EXPECT_EQ(json::parse(h["table_attrs"]["models"].get<std::string>()), s.j["config"]["models"]);
  EXPECT_EQ(json::parse(h["table_attrs"]["labels"].get<std::string>()), json(kModels));
  const json& t = h["table"];
  const std::size_t n = s.j["rows"].size();
  for (auto it = t.begin(); it != t.end(); ++it) {
    EXPECT_EQ(it.value().size(), n) << it.key();
    EXPECT_TRUE(h["units"].contains(it.key())) << it.key();
  }
  EXPECT_EQ(h["units"]["project_seconds"], "s");
  EXPECT_EQ(h["units"]["error_l2"], "1");
  for (std::size_t k = 0; k < n; ++k) {
    const json& r = s.j["rows"][k];
    EXPECT_EQ(t["level"][k], r["level"]);
    EXPECT_EQ(t["order"][k], r["order"]);
    EXPECT_EQ(t["cells"][k], r["cells"]);
    EXPECT_EQ(t["modes"][k], r["modes"]);
    EXPECT_EQ(t["supported"][k].get<int>(), r["supported"].get<bool>() ? 1 : 0);
    EXPECT_EQ(t["gram_error"][k], r["gram_error"]);
    for (std::size_t m = 0; m < kModels.size(); ++m) {
      EXPECT_EQ(t["error_l2"][k][m], r["models"][m]["error_l2"]);  // NaN in HDF5 <-> null in JSON
      EXPECT_EQ(t["error_max"][k][m], r["models"][m]["error_max"]);
      EXPECT_EQ(t["project_seconds"][k][m], r["models"][m]["project_seconds"]);
    }
  }
  EXPECT_EQ(h["support"]["largest_order"].size(), 2u);
}

TEST(CliBenchSweep, EveryReportSectionIsInTheFileTheJsonAndTheReport) {
  const Sweep& s = tiny_sweep();
  ASSERT_EQ(s.exit_code, 0) << s.err;
  ASSERT_EQ(s.h5["sections"].size(), s.j["sections"].size());
  for (auto it = s.j["sections"].begin(); it != s.j["sections"].end(); ++it) {
    const std::string title = it.value()["title"].get<std::string>();
    ASSERT_TRUE(s.h5["sections"].contains(it.key())) << it.key();
    EXPECT_EQ(s.h5["sections"][it.key()]["title"], title);
    EXPECT_EQ(s.h5["sections"][it.key()]["data"], it.value()["data"]);
    EXPECT_NE(s.report.find("## " + title + "\n"), std::string::npos) << title;
    EXPECT_NE(s.report.find(s.h5["sections"][it.key()]["markdown"].get<std::string>()), std::string::npos) << title;
    for (const json& f : it.value()["figures"]) expect_valid_png(s.dir.file("report/" + f.get<std::string>()));
  }
}

TEST(CliBenchSweep, ReportAndFiguresAreWritten) {
  const Sweep& s = tiny_sweep();
  ASSERT_EQ(s.exit_code, 0) << s.err;
  for (const char* heading : {"## Order each level supports", "## Grid and operators per (level, order)", "## Relative L2 error against order",
                              "## Pareto front of time against error", "## Figures"})
    EXPECT_NE(s.report.find(heading), std::string::npos) << heading;
  EXPECT_NE(s.report.find("bench sweep"), std::string::npos);  // the command line
  const json& figs = s.j["figures"];
  ASSERT_EQ(figs.size(), kModels.size() + 2);  // one error figure per model, Pareto, Gram
  for (const json& f : figs) {
    expect_valid_png(s.dir.file("report/" + f.get<std::string>()));
    EXPECT_NE(s.report.find("(" + f.get<std::string>() + ")"), std::string::npos);
  }
  // No staging folder or temporary is left beside the report and the results.
  const auto listing = run_python("import os, sys\nprint(sum(n.startswith('.') for n in os.listdir(sys.argv[1])))", s.dir.path);
  EXPECT_EQ(std::stoi(listing), 0);
}

// Runs a failing sweep and checks: exit code, one line on stderr, no RESULTS.h5 and no report folder.
void expect_refused(const std::vector<std::string>& extra, int code, const std::string& output_override = "",
                    const std::string& report_override = "") {
  TempDir t;
  const std::string out = output_override.empty() ? t.file("r.h5") : output_override;
  const std::string rep = report_override.empty() ? t.file("rep") : report_override;
  std::vector<std::string> args{"bench", "sweep", "--quick", "-q", "-o", out, "--report", rep};
  args.insert(args.end(), extra.begin(), extra.end());
  for (const char* opt : {"--levels", "--orders"})  // small defaults unless the case is about them
    if (std::find(extra.begin(), extra.end(), opt) == extra.end()) args.insert(args.end(), {opt, "1"});
  const auto r = run_cli(args);
  EXPECT_EQ(r.exit_code, code) << r.err;
  ASSERT_FALSE(r.err.empty());
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;  // one line
  EXPECT_TRUE(r.out.empty()) << r.out;
  if (output_override.empty()) { EXPECT_FALSE(exists(out)); }
  if (report_override.empty()) { EXPECT_FALSE(exists(rep)); }
  // Nothing at all (no staging folder, no temporary) in the folder the outputs would have gone to.
  const auto listing = run_python("import os, sys\nprint(len(os.listdir(sys.argv[1])))", t.path);
  EXPECT_EQ(std::stoi(listing), 0);
}

TEST(CliBenchSweep, BadInputIsRefusedWithoutOutput) {
  expect_refused({"--models", "lambert,nosuchmodel"}, 2);
  expect_refused({"--models", "ggx:alpha=9"}, 2);      // out of range
  expect_refused({"--models", "mirror"}, 2);           // delta parts: no pointwise error
  expect_refused({"--models", "lambert,lambert"}, 2);  // listed twice
  expect_refused({"--levels", "3..1"}, 2);
  expect_refused({"--levels", "7"}, 2);
  expect_refused({"--orders", "0..33"}, 2);
  expect_refused({"--orders", "a..b"}, 2);
  expect_refused({"--sampling", "nearest"}, 2);
  expect_refused({"--gram-tol", "0"}, 2);
  expect_refused({}, 5, "/nonexistent-icobrdf-folder/r.h5");
}

TEST(CliBenchSweep, ReportPathThatIsAFileIsRefused) {
  TempDir t;
  std::ofstream(t.file("afile")) << "x";
  const auto r = run_cli({"bench", "sweep", "--quick", "-q", "--levels", "1", "--orders", "0", "-o", t.file("r.h5"), "--report", t.file("afile")});
  EXPECT_EQ(r.exit_code, 5) << r.err;
  EXPECT_FALSE(exists(t.file("r.h5")));
  EXPECT_EQ(slurp(t.file("afile")), "x");
}

TEST(CliBenchSweep, FailureLeavesAnExistingResultsFileAndReportUntouched) {
  TempDir t;
  std::ofstream(t.file("r.h5")) << "old results";
  ::mkdir(t.file("rep").c_str(), 0755);
  // report.md taken by a folder: found only after the sweep ran, before anything is replaced.
  ::mkdir(t.file("rep/report.md").c_str(), 0755);
  std::ofstream(t.file("rep/keep.txt")) << "mine";
  const auto r = run_cli({"bench", "sweep", "--quick", "-q", "--levels", "1", "--orders", "0", "--models", "lambert", "-o", t.file("r.h5"),
                          "--report", t.file("rep")});
  EXPECT_EQ(r.exit_code, 5) << r.err;
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
  EXPECT_EQ(slurp(t.file("r.h5")), "old results");
  EXPECT_EQ(slurp(t.file("rep/keep.txt")), "mine");
  const auto listing = run_python("import os, sys\nprint(sorted(os.listdir(sys.argv[1])))", t.path);
  EXPECT_EQ(listing, "['r.h5', 'rep']\n");  // no staging folder, no temporary left
  const auto inside = run_python("import os, sys\nprint(sorted(os.listdir(sys.argv[1])))", t.file("rep"));
  EXPECT_EQ(inside, "['keep.txt', 'report.md']\n");  // no figure moved in
}

}  // namespace ICOBRDF_UNITY_ID
