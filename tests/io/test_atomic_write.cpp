// Atomic bank writes: refusals leave no file and no temporary; a failure at any point of an overwrite
// (injected through the write fault hook, or a full disk simulated with RLIMIT_FSIZE) leaves the previous
// bank byte for byte intact; a target that is not a regular file (FIFO, link, device) is never replaced.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <stdexcept>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/atomic_write.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::ScratchDir;

icobrdf::BankContents small_bank(const std::string& material) {
  icobrdf::BankContents b;
  b.grid = icobrdf::test::synthetic_grid();
  icobrdf::MaterialRecord m;
  m.name = material;
  m.spectrum = icobrdf::test::synthetic_spectrum(2, 1);
  b.materials = {m};
  return b;
}

// A bank of about 0.9 MB: 3 x 200 x 200 float64 LUT of hashed values (random mantissas barely compress).
icobrdf::BankContents large_bank() {
  icobrdf::BankContents b = small_bank("large");
  auto& m = b.materials[0];
  m.spectrum = icobrdf::test::synthetic_spectrum(2, 3);
  m.spectrum.grid_kind = "test-cells";
  std::uint64_t x = 88172645463325252ull;
  for (int c = 0; c < 3; ++c) {
    Eigen::MatrixXd f(200, 200);
    for (int i = 0; i < 200; ++i)
      for (int r = 0; r < 200; ++r) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;  // xorshift64
        f(i, r) = static_cast<double>(x >> 11) * 0x1.0p-53;
      }
    m.lut.push_back(f);
  }
  return b;
}

struct HookGuard {
  ~HookGuard() { icobrdf::set_write_fault_hook({}); }
};

TEST(AtomicWrite, WritesAndLeavesNoTemporary) {
  ScratchDir dir;
  icobrdf::write_bank(dir / "bank.h5", small_bank("a"));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"bank.h5"});
  EXPECT_EQ(icobrdf::read_bank(dir / "bank.h5").materials.at(0).name, "a");
  icobrdf::write_bank(dir / "bank.h5", small_bank("b"));  // overwrite
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"bank.h5"});
  EXPECT_EQ(icobrdf::read_bank(dir / "bank.h5").materials.at(0).name, "b");
}

TEST(AtomicWrite, NewFileModeFollowsUmask) {
  ScratchDir dir;
  const mode_t old = ::umask(022);
  icobrdf::write_bank(dir / "bank.h5", small_bank("a"));
  ::umask(old);
  struct stat st;
  ASSERT_EQ(::stat((dir / "bank.h5").c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0644u);  // 0666 & ~022
}

TEST(AtomicWrite, RelativePathInCurrentFolder) {
  ScratchDir dir;
  char cwd[4096];
  ASSERT_NE(::getcwd(cwd, sizeof cwd), nullptr);
  ASSERT_EQ(::chdir(dir.path().c_str()), 0);
  EXPECT_NO_THROW(icobrdf::write_bank("bank.h5", small_bank("a")));
  ASSERT_EQ(::chdir(cwd), 0);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"bank.h5"});
}

TEST(AtomicWrite, FolderThatIsARegularFileIsIoError) {
  // Root ignores permission bits, so "not writable" is made with a folder path that is a regular file.
  ScratchDir dir;
  icobrdf::test::write_bytes(dir / "plain.txt", "keep me");
  try {
    icobrdf::write_bank(dir / "plain.txt/bank.h5", small_bank("a"));
    FAIL() << "no error";
  } catch (const icobrdf::IoError& e) {
    EXPECT_NE(std::string(e.what()).find(dir / "plain.txt/bank.h5"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("Not a directory"), std::string::npos) << e.what();
  }
  EXPECT_EQ(icobrdf::test::read_bytes(dir / "plain.txt"), "keep me");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"plain.txt"});
}

TEST(AtomicWrite, MissingFolderIsIoError) {
  ScratchDir dir;
  EXPECT_THROW(icobrdf::write_bank(dir / "no/such/bank.h5", small_bank("a")), icobrdf::IoError);
  EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicWrite, UnwritableFolderIsIoError) {
  // /proc refuses file creation even for root.
  EXPECT_THROW(icobrdf::write_bank("/proc/icobrdf-bank.h5", small_bank("a")), icobrdf::IoError);
}

TEST(AtomicWrite, PathThatIsAFolderIsIoError) {
  ScratchDir dir;
  ASSERT_EQ(::mkdir((dir / "out").c_str(), 0755), 0);
  try {
    icobrdf::write_bank(dir / "out", small_bank("a"));
    FAIL() << "no error";
  } catch (const icobrdf::IoError& e) {
    EXPECT_NE(std::string(e.what()).find("is a folder"), std::string::npos) << e.what();
  }
  EXPECT_THROW(icobrdf::write_bank(dir / "out/", small_bank("a")), icobrdf::IoError);
  struct stat st;
  ASSERT_EQ(::stat((dir / "out").c_str(), &st), 0);
  EXPECT_TRUE(S_ISDIR(st.st_mode));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out"});
}

TEST(AtomicWrite, FailureAtAnyPointKeepsTheOldBank) {
  ScratchDir dir;
  const std::string path = dir / "bank.h5";
  icobrdf::write_bank(path, small_bank("old"));
  const std::string before = icobrdf::test::read_bytes(path);
  HookGuard guard;
  for (const std::string point : {"bank:material", "bank:before-complete", "atomic_write:produced", "atomic_write:synced"}) {
    SCOPED_TRACE(point);
    icobrdf::set_write_fault_hook([&](const std::string& p) {
      if (p == point) throw icobrdf::IoError("injected failure at " + p);
    });
    try {
      icobrdf::write_bank(path, small_bank("new"));
      ADD_FAILURE() << "no error";
    } catch (const icobrdf::IoError& e) {
      EXPECT_EQ(std::string(e.what()), "injected failure at " + point);
    }
    EXPECT_EQ(icobrdf::test::read_bytes(path), before);
    EXPECT_EQ(dir.entries(), std::vector<std::string>{"bank.h5"});  // temporary removed
  }
  icobrdf::set_write_fault_hook({});
  EXPECT_EQ(icobrdf::read_bank(path).materials.at(0).name, "old");
}

TEST(AtomicWrite, ProducerExceptionPropagatesAndRemovesTemporary) {
  ScratchDir dir;
  std::string seen;
  EXPECT_THROW(icobrdf::atomic_write(dir / "x.bin",
                                     [&](const std::string& tmp) {
                                       seen = tmp;
                                       icobrdf::test::write_bytes(tmp, "partial");
                                       throw std::runtime_error("boom");
                                     }),
               std::runtime_error);
  EXPECT_EQ(icobrdf::parent_folder(seen), dir.path());  // temporary in the same folder
  EXPECT_TRUE(dir.entries().empty());
}

TEST(AtomicWrite, DiskFullKeepsTheOldBank) {
  ScratchDir dir;
  const std::string path = dir / "bank.h5";
  icobrdf::write_bank(path, small_bank("old"));
  const std::string before = icobrdf::test::read_bytes(path);
  // In a child, limit file size to 256 KiB (as a nearly full disk would) and ignore SIGXFSZ so writes fail
  // with EFBIG; the 0.9 MB bank cannot fit.
  const auto r = icobrdf::test::run_in_child([&] {
    struct rlimit lim = {256 * 1024, 256 * 1024};
    if (::setrlimit(RLIMIT_FSIZE, &lim) != 0) throw std::runtime_error("setrlimit failed");
    ::signal(SIGXFSZ, SIG_IGN);
    icobrdf::write_bank(path, large_bank());
  });
  EXPECT_FALSE(r.timed_out);
  EXPECT_FALSE(r.signaled);
  EXPECT_EQ(r.kind, "IoError") << r.message;
  if (std::getenv("ICOBRDF_TEST_SHOW_ERRORS")) std::printf("    %s\n", r.message.c_str());
  EXPECT_EQ(r.message.rfind(path, 0), 0u) << r.message;
  EXPECT_EQ(r.err, "");
  EXPECT_EQ(icobrdf::test::read_bytes(path), before);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"bank.h5"});
  // Without the limit the same bank is written.
  EXPECT_NO_THROW(icobrdf::write_bank(path, large_bank()));
  EXPECT_GT(icobrdf::test::read_bytes(path).size(), 512u * 1024u);
}

// Defence in depth: atomic_write itself refuses a target that is not a regular file or a new name (the
// commands check it up front too, icobrdf/io/output_path.hpp), before producing anything, and leaves it alone.
TEST(AtomicWrite, NonRegularTargetsAreRefusedBeforeProducing) {
  ScratchDir dir;
  icobrdf::test::write_bytes(dir / "plain", "keep me");
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0644), 0);
  ASSERT_EQ(::symlink("plain", (dir / "link").c_str()), 0);
  const int fd = ::open((dir / "plain").c_str(), O_RDONLY);
  ASSERT_GE(fd, 0);
  for (const std::string& path : {dir / "fifo", dir / "link", "/proc/self/fd/" + std::to_string(fd), std::string("/dev/null")}) {
    SCOPED_TRACE(path);
    bool produced = false;
    EXPECT_THROW(icobrdf::atomic_write(path, [&](const std::string&) { produced = true; }), icobrdf::IoError);
    EXPECT_FALSE(produced);
    EXPECT_THROW(icobrdf::write_bank(path, small_bank("a")), icobrdf::IoError);
    EXPECT_THROW(icobrdf::atomic_write_text(path, "text"), icobrdf::IoError);
  }
  ::close(fd);
  struct stat st;
  ASSERT_EQ(::lstat((dir / "fifo").c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  ASSERT_EQ(::lstat((dir / "link").c_str(), &st), 0);
  EXPECT_TRUE(S_ISLNK(st.st_mode));
  EXPECT_EQ(icobrdf::test::read_bytes(dir / "plain"), "keep me");
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"fifo", "link", "plain"}));  // no temporary left
}

// The target is checked again just before the rename: a FIFO made at the path while the content was being
// produced is not replaced.
TEST(AtomicWrite, TargetThatBecameAFifoDuringTheWriteIsNotReplaced) {
  ScratchDir dir;
  const std::string path = dir / "out.txt";
  icobrdf::test::write_bytes(path, "old");
  HookGuard guard;
  icobrdf::set_write_fault_hook([&](const std::string& p) {
    if (p != "atomic_write:synced") return;
    ::unlink(path.c_str());
    ASSERT_EQ(::mkfifo(path.c_str(), 0644), 0);
  });
  EXPECT_THROW(icobrdf::atomic_write_text(path, "new"), icobrdf::IoError);
  struct stat st;
  ASSERT_EQ(::lstat(path.c_str(), &st), 0);
  EXPECT_TRUE(S_ISFIFO(st.st_mode));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"out.txt"});  // temporary removed
}

TEST(AtomicWrite, TextIsWrittenWhole) {
  ScratchDir dir;
  icobrdf::atomic_write_text(dir / "a.md", "first");
  icobrdf::atomic_write_text(dir / "a.md", std::string("sec\0ond", 7));
  EXPECT_EQ(icobrdf::test::read_bytes(dir / "a.md"), std::string("sec\0ond", 7));
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"a.md"});
}

TEST(AtomicFile, UncommittedIsRemovedAndCommittedReplacesThePath) {
  ScratchDir dir;
  const std::string path = dir / "f.bin";
  icobrdf::atomic_write_text(path, "old");
  {
    icobrdf::AtomicFile f(path);
    icobrdf::test::write_bytes(f.temp_path(), "half");
    EXPECT_EQ(dir.entries().size(), 2u);  // the old file and the temporary beside it
  }
  EXPECT_EQ(icobrdf::test::read_bytes(path), "old");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"f.bin"});
  icobrdf::AtomicFile f(path);
  icobrdf::test::write_bytes(f.temp_path(), "new");
  f.commit();
  EXPECT_EQ(icobrdf::test::read_bytes(path), "new");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"f.bin"});
}

// A bank written material by material is the bank write_bank writes of the same contents, byte for byte.
TEST(BankWriter, MaterialByMaterialGivesWriteBanksBytes) {
  ScratchDir dir;
  icobrdf::BankContents b = small_bank("a");
  b.created = "2026-11-26T00:00:00Z";
  b.materials.push_back(large_bank().materials.front());
  icobrdf::write_bank(dir / "whole.h5", b);
  {
    icobrdf::BankWriter w(dir / "parts.h5");
    for (const auto& m : b.materials) w.add(m);
    icobrdf::BankContents rest = b;
    rest.materials.clear();
    w.finish(rest);
  }
  EXPECT_EQ(icobrdf::test::read_bytes(dir / "parts.h5"), icobrdf::test::read_bytes(dir / "whole.h5"));
  EXPECT_EQ(dir.entries(), (std::vector<std::string>{"parts.h5", "whole.h5"}));
}

TEST(BankWriter, UnfinishedLeavesNothingAndBadMaterialsAreRefusedOneByOne) {
  ScratchDir dir;
  const std::string path = dir / "bank.h5";
  icobrdf::write_bank(path, small_bank("old"));
  const std::string before = icobrdf::test::read_bytes(path);
  {
    icobrdf::BankWriter w(path);
    w.add(small_bank("a").materials.front());
    EXPECT_THROW(w.add(small_bank("a").materials.front()), icobrdf::ArgumentError);  // the same name twice
    auto nan = small_bank("b").materials.front();
    nan.spectrum.channels[0](1, 1) = std::nan("");
    EXPECT_THROW(w.add(nan), icobrdf::UnsupportedError);
  }  // never finished
  EXPECT_EQ(icobrdf::test::read_bytes(path), before);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"bank.h5"});
}

}  // namespace ICOBRDF_UNITY_ID
