// Output paths (icobrdf/io/output_path.hpp): every kind of existing node that is not a regular file is refused and
// left as it was, a missing or unusable folder is refused, and an output that is one of the inputs (by
// device and inode, whatever the spelling) is refused. Device nodes are not created (mknod needs root):
// FIFOs, sockets, folders and symbolic links stand for the class, /dev/null is only looked at.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/output_path.hpp"
#include "io_test_support.hpp"
#include "special_files.hpp"
#include "tests/support/unity_id.hpp"

namespace ICOBRDF_UNITY_ID {

using icobrdf::test::make_socket;
using icobrdf::test::ScratchDir;

// `check` throws E with a one-line message that starts with `path` and contains `fragment`.
template <class E, class F>
void expect_refused(F check, const std::string& path, const std::string& fragment) {
  try {
    check();
    ADD_FAILURE() << path << ": not refused";
  } catch (const E& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(path, 0), 0u) << m;
    EXPECT_NE(m.find(fragment), std::string::npos) << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

TEST(OutputPath, NewNameAndRegularFileAreAccepted) {
  ScratchDir dir;
  icobrdf::test::write_bytes(dir / "old.h5", "old");
  EXPECT_NO_THROW(icobrdf::check_output_path(dir / "new.h5"));
  EXPECT_NO_THROW(icobrdf::check_output_path(dir / "old.h5", {dir / "other.h5", "model:lambert"}));
  EXPECT_EQ(icobrdf::test::read_bytes(dir / "old.h5"), "old");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"old.h5"});  // nothing created, the probe removed
}

TEST(OutputPath, EveryNodeThatIsNotARegularFileIsRefusedAndLeftAlone) {
  ScratchDir dir;
  icobrdf::test::write_bytes(dir / "plain", "keep me");
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0644), 0);
  ASSERT_EQ(::mkdir((dir / "folder").c_str(), 0755), 0);
  make_socket(dir / "socket");
  ASSERT_EQ(::symlink("fifo", (dir / "link-to-fifo").c_str()), 0);
  ASSERT_EQ(::symlink("plain", (dir / "link-to-file").c_str()), 0);
  ASSERT_EQ(::symlink("/dev/null", (dir / "link-to-null").c_str()), 0);
  ASSERT_EQ(::symlink("nothing-here", (dir / "dangling").c_str()), 0);
  // /proc/self/fd/N of a regular file: what -o /dev/stdout is when stdout is redirected to a file. The
  // rename would replace the link (as root, /dev/stdout itself), never write the file.
  const int fd = ::open((dir / "plain").c_str(), O_RDONLY);
  ASSERT_GE(fd, 0);
  const std::string proc_fd = "/proc/self/fd/" + std::to_string(fd);
  struct Case {
    std::string path, fragment;
  } cases[] = {
      {dir / "fifo", "is a FIFO"},
      {dir / "folder", "is a folder"},
      {dir / "socket", "is a socket"},
      {"/dev/null", "is a character device"},
      {dir / "link-to-fifo", "symbolic link (to 'fifo', a FIFO"},
      {dir / "link-to-file", "symbolic link (to 'plain', a regular file"},
      {dir / "link-to-null", "symbolic link (to '/dev/null', a character device"},
      {dir / "dangling", "symbolic link (to 'nothing-here', missing"},
      {proc_fd, "symbolic link (to '" + dir / "plain" + "', a regular file"},
      {dir / "folder/", "names a folder"},
      {dir / "..", "names a folder"},
  };
  std::vector<std::string> before;
  for (const auto& c : cases) before.push_back(icobrdf::test::node_kind(c.path));
  for (const auto& c : cases) {
    SCOPED_TRACE(c.path);
    expect_refused<icobrdf::IoError>([&] { icobrdf::check_output_target(c.path); }, c.path, c.fragment);
    expect_refused<icobrdf::IoError>([&] { icobrdf::check_output_path(c.path); }, c.path, c.fragment);
  }
  for (size_t i = 0; i < std::size(cases); ++i) EXPECT_EQ(icobrdf::test::node_kind(cases[i].path), before[i]) << cases[i].path;
  ::close(fd);
  EXPECT_EQ(icobrdf::test::read_bytes(dir / "plain"), "keep me");
  EXPECT_EQ(dir.entries().size(), 8u);  // the eight nodes made above, no probe left
}

TEST(OutputPath, MissingOrNonFolderParentIsRefused) {
  ScratchDir dir;
  icobrdf::test::write_bytes(dir / "plain.txt", "keep me");
  expect_refused<icobrdf::IoError>([&] { icobrdf::check_output_path(dir / "no/such/out.h5"); }, dir / "no/such/out.h5",
                                   "No such file or directory");
  expect_refused<icobrdf::IoError>([&] { icobrdf::check_output_path(dir / "plain.txt/out.h5"); }, dir / "plain.txt/out.h5",
                                   "Not a directory");
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"plain.txt"});
}

TEST(OutputPath, FolderWhereNoFileCanBeCreatedIsRefusedUpFront) {
  // /proc refuses new files even for root (permission bits would not: CI runs as root). The target check
  // alone lets it through (atomic_write then fails when it creates its temporary): the up-front check
  // creates a probe file, so a command fails before its work.
  EXPECT_NO_THROW(icobrdf::check_output_target("/proc/icobrdf-out.h5"));
  expect_refused<icobrdf::IoError>([] { icobrdf::check_output_path("/proc/icobrdf-out.h5"); }, "/proc/icobrdf-out.h5",
                                   "cannot create a file in folder /proc");
}

TEST(OutputPath, OutputThatIsAnInputIsRefusedWhateverItsSpelling) {
  ScratchDir dir;
  const std::string bank = dir / "bank.h5";
  icobrdf::test::write_bytes(bank, "forty materials");
  ASSERT_EQ(::link(bank.c_str(), (dir / "hard.h5").c_str()), 0);
  ASSERT_EQ(::symlink("bank.h5", (dir / "soft.h5").c_str()), 0);
  icobrdf::test::write_bytes(dir / "s.csv", "samples");
  struct Case {
    std::string output, input;
  } cases[] = {
      {bank, bank + "#g1"},                       // bank extract BANK.h5#g1 -o BANK.h5
      {bank, bank},                               // smooth LUT.h5 -o LUT.h5
      {dir / "hard.h5", bank + "#g1"},            // a hard link: same inode, other name
      {bank, dir / "soft.h5#g1"},                 // the input through a symbolic link
      {bank, dir.path() + "/./bank.h5"},          // another spelling of the same path
      {dir / "s.csv", "samples:" + dir / "s.csv#radians"},  // a SOURCE with a kind prefix and options
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.output + " <- " + c.input);
    expect_refused<icobrdf::ArgumentError>([&] { icobrdf::check_output_path(c.output, {"model:lambert", c.input}); }, c.output,
                                           "is the same file as the input '" + c.input + "'");
  }
  EXPECT_EQ(icobrdf::test::read_bytes(bank), "forty materials");
  // Other files, models and inputs that do not exist are no reason to refuse.
  EXPECT_NO_THROW(icobrdf::check_output_path(dir / "new.h5", {bank + "#g1"}));
  EXPECT_NO_THROW(icobrdf::check_output_path(dir / "s.csv", {bank, "model:lambert", dir / "missing.h5#x"}));
}

}  // namespace ICOBRDF_UNITY_ID
