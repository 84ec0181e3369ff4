// `mpirun -np 2 --oversubscribe icobrdf fit MODEL` (icobrdf/cluster/distributed_projection.hpp, the operators
// split by rows: icobrdf/core/projection/row_split_projection.hpp): the spectrum equals the one-process fit's to rounding
// (kSplitRelTol below), two distributed runs give the same bits, each rank reports its peak memory, a failing rank ends the fit with one
// line naming it and no output, and `bench streaming` reports every rank. Level 3, so each run takes well
// under a second. Skipped when the MPI layer was not built.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "icobrdf/core/models/model_registry.hpp"
#include "icobrdf/core/fit/sample_fit.hpp"
#include "icobrdf/io/merl.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "tests/cli/cli_runner.hpp"
#include "tests/support/unity_id.hpp"

using icobrdf::test::cli_command;
using icobrdf::test::CliResult;
using icobrdf::test::run_cli;
using icobrdf::test::run_shell;
using icobrdf::test::shell_quote;
using icobrdf::test::TempDir;
using nlohmann::json;

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

constexpr int kLevel = 3, kOrder = 6;
// Two ranks against one process, relative to max|C|: under mpirun the fit splits the operators by rows
// (icobrdf/core/projection/row_split_projection.hpp), so P comes from G summed in another order and the pairs of
// blocks are summed in another order than the one process's blocks: a few ulps times cond(G) (below 2 here)
// and a few hundred roundings. 1e-12 is 100x that and far below a missing or doubled pair of blocks (tests/
// core/test_row_split_projection.cpp checks a part alone is off by more than 1e-3).
constexpr double kSplitRelTol = 1e-12;

const std::string kMpiEnv = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=1 ";

std::string mpirun(int ranks = 2) { return shell_quote(ICOBRDF_MPIEXEC) + " -q -np " + std::to_string(ranks) + " --oversubscribe"; }

CliResult run_mpi(const std::vector<std::string>& args) { return run_shell(kMpiEnv + cli_command(args, mpirun())); }

std::vector<std::string> fit_args(const std::string& source, const std::string& out) {
  return {"fit", source, "--level", std::to_string(kLevel), "--order", std::to_string(kOrder), "-o", out, "--json"};
}

bool exists(const std::string& path) { return std::ifstream(path).good(); }

class FitMpi : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!ICOBRDF_MPI_BUILT) GTEST_SKIP() << "the MPI layer was not built (no MPI found by CMake; scripts/install-deps.sh installs OpenMPI)";
  }
};

// Isotropic reciprocal GGX (the triangle of D2 orbits: blocks of growing cost) in f form, and a diffuse +
// mirror model (g form with cell averages: the full path; the delta is added once, after the reduction).
TEST_F(FitMpi, TwoRanksAgreeWithOneProcessToRoundingAndWithEachOtherBitwise) {
  struct Case {
    std::string spec;
    bool cosine;
  };
  for (const Case& m : {Case{"ggx:alpha=0.3", false}, Case{"0.7*lambert+0.3*mirror", true}}) {
    TempDir d;
    const std::string one = d.file("one.h5"), two = d.file("two.h5"), again = d.file("again.h5");
    setenv("OMP_NUM_THREADS", "1", 1);
    const auto a = run_cli(fit_args("model:" + m.spec, one));
    unsetenv("OMP_NUM_THREADS");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    const auto b = run_mpi(fit_args("model:" + m.spec, two));
    ASSERT_EQ(b.exit_code, 0) << b.err << b.out;
    const auto c = run_mpi(fit_args("model:" + m.spec, again));
    ASSERT_EQ(c.exit_code, 0) << c.err << c.out;
    // Rank 0 alone reports: one JSON document, saying 2 ranks.
    const json j = json::parse(b.out);
    EXPECT_EQ(j.at("ranks").get<int>(), 2) << b.out;
    EXPECT_FALSE(json::parse(a.out).contains("ranks")) << "one process reports as before";
    const Eigen::MatrixXd c1 = read_spectrum_file(one).channels.at(0), c2 = read_spectrum_file(two).channels.at(0);
    const Eigen::MatrixXd c3 = read_spectrum_file(again).channels.at(0);
    EXPECT_LE((c2 - c1).cwiseAbs().maxCoeff(), kSplitRelTol * c1.cwiseAbs().maxCoeff()) << m.spec;
    EXPECT_EQ((c3 - c2).cwiseAbs().maxCoeff(), 0.0) << m.spec << ": two runs on 2 ranks must give the same bits";
    // Each rank reports its peak memory.
    ASSERT_EQ(j.at("peak_rss_bytes_per_rank").size(), 2u) << b.out;
  }
}

// More than two ranks: the ring of blocks of P takes floor(R / 2) steps for a reciprocal model (R = 4: the
// pair half way round is split between its two ranks; R = 3: no such pair) and R - 1 steps for a
// non-reciprocal g form (an anisotropic lobe with --cosine: every ordered pair of blocks). Each agrees with
// one process to rounding.
TEST_F(FitMpi, ThreeAndFourRanksAgreeWithOneProcessToRounding) {
  struct Case {
    std::string spec;
    bool cosine;
  };
  for (const Case& m : {Case{"ggx:alpha=0.3", false}, Case{"ggx-aniso:alpha_x=0.2,alpha_y=0.4,azimuth=30", true}}) {
    TempDir d;
    auto args = fit_args("model:" + m.spec, d.file("one.h5"));
    if (m.cosine) args.push_back("--cosine");
    setenv("OMP_NUM_THREADS", "1", 1);
    const auto a = run_cli(args);
    unsetenv("OMP_NUM_THREADS");
    ASSERT_EQ(a.exit_code, 0) << a.err;
    const Eigen::MatrixXd c1 = read_spectrum_file(d.file("one.h5")).channels.at(0);
    for (int ranks : {3, 4}) {
      const std::string out = d.file(std::to_string(ranks) + ".h5");
      *(std::find(args.begin(), args.end(), "-o") + 1) = out;
      const auto b = run_shell(kMpiEnv + cli_command(args, mpirun(ranks)));
      ASSERT_EQ(b.exit_code, 0) << m.spec << " on " << ranks << " ranks: " << b.err << b.out;
      EXPECT_EQ(json::parse(b.out).at("ranks").get<int>(), ranks) << b.out;
      const Eigen::MatrixXd c = read_spectrum_file(out).channels.at(0);
      EXPECT_LE((c - c1).cwiseAbs().maxCoeff(), kSplitRelTol * c1.cwiseAbs().maxCoeff()) << m.spec << " on " << ranks << " ranks";
    }
  }
}

// Messages in pieces (icobrdf/cluster/cluster.hpp): with ICOBRDF_MPI_PIECE_BYTES=4000 every block of P in
// the ring (about 330 cells x 28 modes x 8 bytes = 74 kB on 2 ranks, 49 kB on 3) and every exchanged C
// (6.3 kB) goes as a header and pieces. The spectrum is the same bits as with whole messages; a bad value
// is a one-line error.
TEST_F(FitMpi, MessagesInPiecesGiveTheSameBits) {
  TempDir d;
  for (int ranks : {2, 3}) {
    const std::string whole = d.file("whole.h5"), pieces = d.file("pieces.h5");
    const std::string np = mpirun(ranks);
    const auto a = run_shell(kMpiEnv + cli_command(fit_args("model:ggx:alpha=0.3", whole), np));
    ASSERT_EQ(a.exit_code, 0) << a.err;
    const auto b = run_shell(kMpiEnv + "ICOBRDF_MPI_PIECE_BYTES=4000 " + cli_command(fit_args("model:ggx:alpha=0.3", pieces), np));
    ASSERT_EQ(b.exit_code, 0) << b.err;
    EXPECT_EQ((read_spectrum_file(pieces).channels.at(0) - read_spectrum_file(whole).channels.at(0)).cwiseAbs().maxCoeff(), 0.0)
        << ranks << " ranks";
    std::remove(whole.c_str());
    std::remove(pieces.c_str());
  }
  // A bad value is refused before MPI starts, by every rank alike: rank 0's line alone (the others end
  // quietly), with the usage exit code 2.
  for (int ranks : {2, 3}) {
    const auto c = run_shell(kMpiEnv + "ICOBRDF_MPI_PIECE_BYTES=0 " + cli_command(fit_args("model:ggx:alpha=0.3", d.file("x.h5")), mpirun(ranks)));
    EXPECT_EQ(c.exit_code, 2) << c.err;
    EXPECT_EQ(c.err, "icobrdf: error: ICOBRDF_MPI_PIECE_BYTES: '0', expected a byte count from 1 to 2147483647\n") << ranks << " ranks";
    EXPECT_FALSE(exists(d.file("x.h5")));
  }
}

// Every rank fails the same way after the ranks agreed on the set-up (order 8 is beyond the Gram tolerance
// of a level-3 grid; each rank checks its G): exactly one line, rank 0's, every time. Each rank prints while
// MPI still holds the ranks together (cli/error_report.hpp): printed after MPI_Finalize, rank 0's line was
// lost in 3 of 42 runs on 3-4 ranks, replaced by the SIGTERM line, because mpirun stops every rank as soon
// as one exits non-zero. kRepeats runs make a recurrence of that likely to be seen (this test with 6
// repeats failed 1 run in 3 on that build).
TEST_F(FitMpi, AnErrorOnEveryRankGivesRankZerosLineEveryTime) {
  constexpr int kRepeats = 10;
  TempDir d;
  const std::string out = d.file("out.h5");
  const std::vector<std::string> args = {"fit", "model:ggx:alpha=0.3", "--level", "3", "--order", "8", "-o", out};
  for (int run = 0; run < kRepeats; ++run) {
    const auto r = run_shell(kMpiEnv + cli_command(args, mpirun(3)));
    EXPECT_EQ(r.exit_code, 4) << r.err;  // kExitUnsupported
    EXPECT_FALSE(exists(out));
    std::istringstream err(r.err);
    std::vector<std::string> lines;
    for (std::string line; std::getline(err, line);) lines.push_back(line);
    ASSERT_EQ(lines.size(), 1u) << "run " << run << ": " << r.err;
    EXPECT_EQ(lines[0].rfind("icobrdf: error: on rank 0 of 3: order 8 exceeds what a grid of 656 cells resolves", 0), 0u) << lines[0];
  }
}

// A source that projects nothing (a stored spectrum, re-expanded exactly): each rank fits it whole and rank
// 0 says so, although the split context made its own exchanges (G and the empty one).
// A usage error is found before MPI starts, by every rank alike (each parses the same command line): rank 0
// alone prints it and mpirun returns its usage code (the other ranks exit quietly); the help is printed once.
TEST_F(FitMpi, AUsageErrorIsPrintedOnceNotOncePerRank) {
  TempDir d;
  const std::string out = d.file("out.h5");
  const auto r = run_shell(kMpiEnv + cli_command({"fit", "model:ggx:alpha=0.3", "--level", "3", "--no-such-option", "-o", out}, mpirun(3)));
  EXPECT_EQ(r.exit_code, 2) << r.err;  // kExitUsage
  EXPECT_FALSE(exists(out));
  std::istringstream err(r.err);
  std::vector<std::string> lines;
  for (std::string line; std::getline(err, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_NE(lines[0].find("--no-such-option"), std::string::npos) << lines[0];
  const auto help = run_shell(kMpiEnv + cli_command({"fit", "--help"}, mpirun(2)));
  EXPECT_EQ(help.exit_code, 0) << help.err;
  ASSERT_NE(help.out.find("Usage:"), std::string::npos) << help.out;
  EXPECT_EQ(help.out.find("Usage:"), help.out.rfind("Usage:")) << "help printed once: " << help.out;
}

TEST_F(FitMpi, ASourceWithoutProjectionIsNotedAsFittedWhole) {
  TempDir d;
  const std::string stored = d.file("stored.h5"), out = d.file("out.h5");
  const auto a = run_cli(fit_args("model:ggx:alpha=0.3", stored));
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const auto b = run_mpi(fit_args(stored, out));
  ASSERT_EQ(b.exit_code, 0) << b.err << b.out;
  EXPECT_NE(b.err.find("is not fitted by streaming projection; each of the 2 ranks fitted it whole"), std::string::npos) << b.err;
  EXPECT_EQ((read_spectrum_file(out).channels.at(0) - read_spectrum_file(stored).channels.at(0)).cwiseAbs().maxCoeff(), 0.0)
      << "the same order: re-expansion is the identity";
}

// A MERL table's least-squares fit under mpirun (icobrdf/core/fit/sample_fit.hpp SampleFitSplit): each rank
// passes over its part of the table's 1.46 million samples, and the normal equations and each refinement
// pass are summed over the ranks. 2 ranks and 3 (parts of unequal size) agree with one process to
// rounding, two runs on 2 ranks give the same bits, and the ranks say they split the samples.
TEST_F(FitMpi, AMerlFitSplitsItsSamplesOverTheRanks) {
  // Normal equations summed in another order differ by a few roundings of G; the refined solution then
  // differs by about cond(W^(1/2) A) eps relative (Bjorck, sec. 2.9); 1000 such roundings, relative to
  // max|C|, is far below what a missing or doubled part of the samples changes (a third of a GGX table's
  // samples carries a third of every sum).
  constexpr double kRoundings = 1000.0;
  TempDir d;
  const std::string table = d.file("ggx.binary");
  write_merl(table, *parse_model("ggx:alpha=0.3"));
  const auto args = [&](const std::string& out) {
    return std::vector<std::string>{"fit", table, "--level", "3", "--order", "6", "-o", out, "--json"};
  };
  setenv("OMP_NUM_THREADS", "1", 1);
  const auto a = run_cli(args(d.file("one.h5")));
  unsetenv("OMP_NUM_THREADS");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const json ja = json::parse(a.out);
  const double condition = ja.at("sample_fit").at("condition_of_kept_part").get<double>();
  ASSERT_TRUE(condition >= 1.0 && condition < kNormalEquationsMaxCondition) << a.out;
  const Eigen::MatrixXd one = read_spectrum_file(d.file("one.h5")).channels.at(0);
  const double bound = kRoundings * condition * std::numeric_limits<double>::epsilon() * one.cwiseAbs().maxCoeff();
  for (int ranks : {2, 3}) {
    const std::string out = d.file("r" + std::to_string(ranks) + ".h5");
    const auto b = run_shell(kMpiEnv + cli_command(args(out), mpirun(ranks)));
    ASSERT_EQ(b.exit_code, 0) << b.err << b.out;
    const json j = json::parse(b.out);
    EXPECT_EQ(j.at("split").get<std::string>(), "samples") << b.out;
    EXPECT_EQ(b.err.find("fitted it whole"), std::string::npos) << b.err;
    EXPECT_EQ(j.at("sample_fit").at("samples").get<long long>(), ja.at("sample_fit").at("samples").get<long long>());
    const Eigen::MatrixXd c = read_spectrum_file(out).channels.at(0);
    EXPECT_LE((c - one).cwiseAbs().maxCoeff(), bound) << ranks << " ranks";
  }
  const auto again = run_shell(kMpiEnv + cli_command(args(d.file("again.h5")), mpirun(2)));
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_EQ((read_spectrum_file(d.file("again.h5")).channels.at(0) - read_spectrum_file(d.file("r2.h5")).channels.at(0)).cwiseAbs().maxCoeff(), 0.0)
      << "two runs on 2 ranks must give the same bits";
}

// CSV samples under mpirun, every choice automatic: the order by 5-fold cross-validation (each fold's normal
// equations summed over the ranks), lambda by GCV. 2 ranks choose as one process does and reach its fit.
TEST_F(FitMpi, ACsvSampleFitChoosesAsOneProcessDoes) {
  constexpr double kRoundings = 1000.0;  // as for the MERL table above
  TempDir d;
  const std::string csv = d.file("s.csv");
  {
    std::ofstream o(csv);
    o << "theta_i,phi_i,theta_r,phi_r,value\n";
    std::mt19937 g(17);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    char line[240];
    for (int k = 0; k < 3000; ++k) {  // a smooth anisotropic function plus 1% noise
      const double ti = std::acos(u(g)), tr = std::acos(u(g)), pi = 2 * M_PI * u(g), pr = 2 * M_PI * u(g);
      const double f = 0.3 + 0.1 * std::cos(ti) * std::cos(tr) + 0.05 * std::sin(ti) * std::sin(tr) * std::cos(pi - pr + 0.3) + 0.003 * (u(g) - 0.5);
      std::snprintf(line, sizeof line, "%.12f,%.12f,%.12f,%.12f,%.17g\n", ti * 180 / M_PI, pi * 180 / M_PI, tr * 180 / M_PI, pr * 180 / M_PI, f);
      o << line;
    }
  }
  const auto args = [&](const std::string& out) { return std::vector<std::string>{"fit", csv, "--level", "3", "-o", out, "--json"}; };
  setenv("OMP_NUM_THREADS", "1", 1);
  const auto a = run_cli(args(d.file("one.h5")));
  unsetenv("OMP_NUM_THREADS");
  ASSERT_EQ(a.exit_code, 0) << a.err;
  const json ja = json::parse(a.out);
  ASSERT_EQ(ja.at("sample_fit").at("order_choice").get<std::string>(), "cross-validation") << a.out;
  const auto b = run_mpi(args(d.file("two.h5")));
  ASSERT_EQ(b.exit_code, 0) << b.err << b.out;
  const json jb = json::parse(b.out);
  EXPECT_EQ(jb.at("split").get<std::string>(), "samples") << b.out;
  EXPECT_EQ(jb.at("order").get<int>(), ja.at("order").get<int>());
  const double condition = ja.at("sample_fit").at("condition_of_kept_part").get<double>();
  const Eigen::MatrixXd one = read_spectrum_file(d.file("one.h5")).channels.at(0), two = read_spectrum_file(d.file("two.h5")).channels.at(0);
  ASSERT_EQ(one.rows(), two.rows());
  EXPECT_LE((two - one).cwiseAbs().maxCoeff(), kRoundings * condition * std::numeric_limits<double>::epsilon() * one.cwiseAbs().maxCoeff());
  // The CV figure sums the folds' refits, each a solve whose rounding its own fold's condition amplifies (not
  // reported; the kept part's condition above bounds the whole fit only): 1e-10 relative (5e5 ulps) admits that
  // rounding and nothing else, since another order or lambda changes the figure in its leading digits.
  constexpr double kCvRoundingRel = 1e-10;
  const double cv1 = ja.at("sample_fit").at("cv_rms").get<double>(), cv2 = jb.at("sample_fit").at("cv_rms").get<double>();
  EXPECT_NEAR(cv2, cv1, kCvRoundingRel * cv1);
}

// A sample fit that the samples do not bound (samples in a 5-degree cap cannot bound an order-2 fit elsewhere:
// the scale check) is regularized instead of refused (a behaviour change: it was exit 4 with rank 0's line): the
// ranks, each with the same summed figures, take the same lambda as one process, and rank 0 writes the file.
TEST_F(FitMpi, AnUnboundedSampleFitIsRegularizedAlikeOnEveryRank) {
  TempDir d;
  const std::string csv = d.file("cap.csv"), out = d.file("cap.h5");
  {
    std::ofstream o(csv);
    o << "theta_i,phi_i,theta_r,phi_r,value\n";
    std::mt19937 g(5);
    std::uniform_real_distribution<double> th(0, 5), ph(0, 360), v(0.3, 0.35);
    for (int k = 0; k < 200; ++k) o << th(g) << "," << ph(g) << "," << th(g) << "," << ph(g) << "," << v(g) << "\n";
  }
  const std::vector<std::string> args{"fit", csv + "#tikhonov=1e-12", "--order", "2", "--isotropic", "-q", "--json", "-o", out};
  const auto one = run_cli(args);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  std::remove(out.c_str());
  const auto r = run_mpi(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(exists(out));
  const json ja = json::parse(one.out), jb = json::parse(r.out);
  EXPECT_EQ(jb.at("sample_fit").at("tikhonov_choice").get<std::string>(), "smallest bounding lambda");
  // The same grid point; the grid's scale (the largest eigenvalue of the summed normal equations) differs in its
  // last bits with the order of the sums, and adjacent grid points differ by 26%.
  constexpr double kSameGridPoint = 1e-10;
  const double la = ja.at("sample_fit").at("tikhonov").get<double>(), lb = jb.at("sample_fit").at("tikhonov").get<double>();
  EXPECT_NEAR(lb, la, kSameGridPoint * la) << "the same grid point";
}

// Rank 1 alone gets a memory budget too small for the fit (mpirun's MPMD form: a second program context
// with its own environment): the fit fails, no spectrum is written, and the one error line names rank 1.
TEST_F(FitMpi, AFailingRankEndsTheFitWithOneLineNamingIt) {
  TempDir d;
  const std::string out = d.file("out.h5");
  const auto args = fit_args("model:ggx:alpha=0.3", out);
  std::string cmd = kMpiEnv + shell_quote(ICOBRDF_MPIEXEC) + " -q -np 1 --oversubscribe " + shell_quote(ICOBRDF_CLI_PATH);
  for (const auto& x : args) cmd += " " + shell_quote(x);
  cmd += " : -np 1 env ICOBRDF_MEMORY_BUDGET=1000 " + shell_quote(ICOBRDF_CLI_PATH);
  for (const auto& x : args) cmd += " " + shell_quote(x);
  const auto r = run_shell(cmd);
  EXPECT_NE(r.exit_code, 0) << r.err;
  EXPECT_FALSE(exists(out)) << "no output after a failed rank";
  std::istringstream err(r.err);
  std::vector<std::string> lines;
  for (std::string line; std::getline(err, line);)
    if (line.rfind("icobrdf:", 0) == 0) lines.push_back(line);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_NE(lines[0].find("icobrdf: error: on rank 1 of 2: a fit at level 3, order 6 needs about"), std::string::npos) << lines[0];
}

// bench streaming under mpirun: rank 0 reports both ranks' peak memory and the same C as one process (the
// max|C| and Frobenius figures, to rounding). The ranks split the operators by rows, as `fit` does; three
// repeats reuse the context (two exchanges) and make one sum of C each, so a miscount of the exchanges
// would hang or fail here. With --every 2 the ranks still split the operators and sample the batches.
TEST_F(FitMpi, BenchStreamingReportsEveryRank) {
  std::vector<std::string> args = {"bench", "streaming", "model:ggx:alpha=0.3", "--level", std::to_string(kLevel), "--order",
                                   std::to_string(kOrder), "--json", "--repeat", "3"};
  const auto r = run_mpi(args);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const json j = json::parse(r.out);
  EXPECT_EQ(j.at("ranks").get<int>(), 2);
  EXPECT_EQ(j.at("operators").get<std::string>(), "split by rows");
  EXPECT_EQ(j.at("projection_seconds_all").size(), 3u);
  ASSERT_EQ(j.at("peak_rss_bytes_per_rank").size(), 2u);
  for (const auto& b : j.at("peak_rss_bytes_per_rank")) EXPECT_GT(b.get<double>(), 1e6);
  EXPECT_GT(j.at("projection_seconds").get<double>(), 0.0);
  const auto one = run_cli(args);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  const json k = json::parse(one.out);
  EXPECT_EQ(k.at("peak_rss_bytes_per_rank").size(), 1u);
  for (const char* figure : {"max_abs_coefficient", "frobenius_norm"}) {
    const double m1 = k.at(figure).get<double>(), m2 = j.at(figure).get<double>();
    EXPECT_LE(std::abs(m2 - m1), kSplitRelTol * m1) << figure;
  }
  // --every 2: the ranks still split the operators by rows and project every other batch of incident rows
  // of each pair of blocks, so the matrices are not C.
  args.insert(args.end(), {"--every", "2"});
  const auto e = run_mpi(args);
  ASSERT_EQ(e.exit_code, 0) << e.err;
  const json je = json::parse(e.out);
  EXPECT_EQ(je.at("operators").get<std::string>(), "split by rows");
  EXPECT_NE(je.at("frobenius_norm").get<double>(), j.at("frobenius_norm").get<double>()) << "every other batch only";
  EXPECT_EQ(je.at("every").get<int>(), 2);
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
