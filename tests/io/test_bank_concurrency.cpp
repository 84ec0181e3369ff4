// Readers and killed writers: a reader looping while the bank is rewritten always sees one complete bank,
// and a writer killed with SIGKILL at arbitrary moments leaves the path absent or holding a complete bank
// (only stale ".<name>.tmp-*" temporaries may remain beside it).
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <random>
#include <set>
#include <thread>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::ScratchDir;

// Rewrites per child in the reader test; each takes some tens of milliseconds.
constexpr int kRewrites = 30;
// SIGKILL repetitions: at least 50, so that the delays drawn below land in every phase of a write.
constexpr int kKills = 50;
// Kill delays are drawn uniformly from [0, kMaxKillDelayUs): a bank write here takes about 5 ms (13 ms for
// the first in a process), so kills land before, during and after the first rename and later ones.
constexpr int kMaxKillDelayUs = 15000;

icobrdf::BankContents bank_named(const std::string& material, int cells) {
  icobrdf::BankContents b;
  b.grid = icobrdf::test::synthetic_grid();
  icobrdf::MaterialRecord m;
  m.name = material;
  m.spectrum = icobrdf::test::synthetic_spectrum(4, 3);
  m.spectrum.grid_kind = "test-cells";
  for (int c = 0; c < 3; ++c) m.lut.push_back(Eigen::MatrixXd::Constant(cells, cells, 0.25 * (c + 1)));
  b.materials = {m};
  return b;
}

TEST(BankConcurrency, ReaderDuringRewritesSeesCompleteBanks) {
  ScratchDir dir;
  const std::string path = dir / "bank.h5";
  icobrdf::write_bank(path, bank_named("a", 60));
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    try {
      for (int k = 0; k < kRewrites; ++k) icobrdf::write_bank(path, bank_named(k % 2 ? "a" : "b", k % 2 ? 60 : 90));
    } catch (...) {
      ::_exit(1);
    }
    ::_exit(0);
  }
  int reads = 0, status = 0;
  std::set<std::string> seen;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    try {
      const auto b = icobrdf::read_bank(path);
      ASSERT_EQ(b.materials.size(), 1u);
      const auto& m = b.materials[0];
      seen.insert(m.name);
      // "a" banks carry 60-cell LUTs, "b" banks 90-cell ones: a mix would be a torn read.
      EXPECT_EQ(m.lut.at(0).rows(), m.name == "a" ? 60 : 90);
      ++reads;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "read " << reads << " failed: " << e.what();
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      break;
    }
  }
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  EXPECT_GT(reads, 0);
  std::printf("    %d reads during %d rewrites saw banks %zu distinct\n", reads, kRewrites, seen.size());
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"bank.h5"});
}

TEST(BankConcurrency, SigkillLeavesAbsentOrCompleteBank) {
  ScratchDir dir;
  const std::string path = dir / "bank.h5";
  std::mt19937 rng(20261122);
  std::uniform_int_distribution<int> delay(0, kMaxKillDelayUs - 1);
  int absent = 0, complete = 0;
  for (int k = 0; k < kKills; ++k) {
    // Even rounds start without a bank; odd ones start from a complete bank, which must never disappear.
    const bool had_bank = k % 2 == 1;
    if (had_bank)
      icobrdf::write_bank(path, bank_named("old", 60));
    else
      ::unlink(path.c_str());
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
      try {
        for (int w = 0;; ++w) icobrdf::write_bank(path, bank_named(w % 2 ? "odd" : "even", 120));
      } catch (...) {
        ::_exit(1);
      }
    }
    std::this_thread::sleep_for(std::chrono::microseconds(delay(rng)));
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "writer failed on its own at kill " << k;
    if (::access(path.c_str(), F_OK) != 0) {
      EXPECT_FALSE(had_bank) << "kill " << k << " removed the previous bank";
      ++absent;
    } else {
      const auto r = icobrdf::test::run_in_child([&] { icobrdf::read_bank(path); });
      EXPECT_EQ(r.kind, "ok") << "kill " << k << ": " << r.message;
      ++complete;
    }
    for (const auto& e : dir.entries())
      EXPECT_TRUE(e == "bank.h5" || e.rfind(".bank.h5.tmp-", 0) == 0) << "unexpected file " << e;
  }
  std::printf("    %d kills: %d left no bank, %d a complete bank\n", kKills, absent, complete);
  EXPECT_GT(complete, 0);
  EXPECT_GT(absent, 0);
}

}  // namespace ICOBRDF_UNITY_ID
