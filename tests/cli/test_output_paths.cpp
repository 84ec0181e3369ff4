// Output paths of every command that writes (issue #19, "what exists must not be destroyed"): a FIFO, a
// folder, a socket, a symbolic link (to a FIFO, a file or /dev/null), a missing folder, or a folder where no
// file can be created, at the output path is refused with a one-line error (exit 5) before any work, and
// left exactly as it was; an output that is one of the command's own inputs is refused (exit 2) and the
// input kept byte for byte. The check is icobrdf/io/output_path.hpp (tests/io/test_output_path.cpp tests it piece
// by piece); atomic_write applies its first half again (tests/io/test_atomic_write.cpp).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "tests/cli/cli_runner.hpp"
#include "tests/io/special_files.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf::test {
namespace ICOBRDF_UNITY_ID {

// Two materials: enough for `bank extract` to lose one, and to show that `bank build` fits none of them.
const char* kScene = R"([bank]
level = 1
levels = [1]
order_max = 2
target = 0.01

[[material]]
name = "a"
source = "model:lambert:albedo=0.5"

[[material]]
name = "b"
source = "model:lambert:albedo=0.8"
)";

std::string shell_output(const std::string& cmd) {
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  char buf[4096];
  size_t n = 0;
  while (p && (n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  if (p) ::pclose(p);
  return out;
}

// Everything under a folder: names, types, link targets, sizes, and the bytes of the regular files.
std::string listing(const std::string& dir) {
  return shell_output("cd " + shell_quote(dir) + " && find . -printf '%p %y %l %s\\n' | sort && find . -type f | sort | xargs -r cat");
}

const std::string kOut = "OUT";

std::vector<std::string> with_output(std::vector<std::string> args, const std::string& out) {
  std::replace(args.begin(), args.end(), kOut, out);
  return args;
}

std::string joined(const std::vector<std::string>& args) {
  std::string s;
  for (const auto& a : args) s += (s.empty() ? "" : " ") + a;
  return s;
}

// Inputs made once (by the first test that runs) and shared: a spectrum file, a LUT file, a two-material
// bank and its scene. Made in SetUp, not SetUpTestSuite, so that a failure fails the tests (CTest counts
// the tests of a failed suite set-up as skipped).
class OutputPaths : public ::testing::Test {
 protected:
  void SetUp() override {
    if (inputs_) return;
    inputs_ = new TempDir;  // removed by TearDownTestSuite
    std::ofstream(scene()) << kScene;
    for (const auto& args : std::vector<std::vector<std::string>>{
             {"fit", "model:lambert", "--order", "2", "--level", "2", "-o", spectrum()},
             {"lut", "model:lambert", "--level", "2", "--order", "2", "-o", lut()},
             {"bank", "build", scene(), "-o", bank(), "--quiet"}}) {
      const auto r = run_cli(args);
      ASSERT_EQ(r.exit_code, 0) << joined(args) << ": " << r.err;
    }
  }
  static void TearDownTestSuite() {
    delete inputs_;
    inputs_ = nullptr;
  }
  static std::string spectrum() { return inputs_->file("s.h5"); }
  static std::string lut() { return inputs_->file("lut.h5"); }
  static std::string bank() { return inputs_->file("bank.h5"); }
  static std::string scene() { return inputs_->file("scene.toml"); }

  // Every command that writes a file, with kOut where its output path goes.
  static std::vector<std::vector<std::string>> writers(const std::string& scratch) {
    return {
        {"fit", "model:lambert", "--order", "0", "--level", "0", "-o", kOut},
        {"lut", "model:lambert", "--level", "0", "--order", "0", "-o", kOut},
        {"smooth", lut(), "--order", "0", "-o", kOut},
        {"export", spectrum(), "--format", "scatmech", "-o", kOut},
        {"bank", "extract", bank() + "#a", "-o", kOut},
        {"bank", "build", scene(), "-o", kOut},
        {"plot", "slice", "model:lambert", "--order", "0", "--level", "1", "-o", kOut},
        {"plot", "spectrum", spectrum(), "-o", kOut},
        {"plot", "sphere", "model:lambert", "--size", "16", "-o", kOut},
        {"grid", "--level", "1", "--export-obj", kOut},
        {"bench", "sweep", "--quick", "-q", "--levels", "1", "--orders", "0", "--report", scratch + "/report", "-o", kOut},
    };
  }

  static TempDir* inputs_;
};
TempDir* OutputPaths::inputs_ = nullptr;

TEST_F(OutputPaths, NodesThatAreNotRegularFilesAreRefusedBeforeAnyWorkAndLeftAlone) {
  const size_t commands = writers("").size();
  for (size_t i = 0; i < commands; ++i) {
    TempDir t;
    const auto args = writers(t.path)[i];
    SCOPED_TRACE(joined(args));
    ASSERT_EQ(::mkfifo(t.file("fifo").c_str(), 0644), 0);
    ASSERT_EQ(::mkdir(t.file("folder").c_str(), 0755), 0);
    std::ofstream(t.file("folder/inside.txt")) << "inside";
    std::ofstream(t.file("plain.h5")) << "plain";
    make_socket(t.file("socket"));
    ASSERT_EQ(::symlink("fifo", t.file("link-to-fifo").c_str()), 0);
    ASSERT_EQ(::symlink("plain.h5", t.file("link-to-file").c_str()), 0);
    ASSERT_EQ(::symlink("/dev/null", t.file("link-to-null").c_str()), 0);
    const std::string before = listing(t.path);
    for (const std::string& out : {t.file("fifo"), t.file("folder"), t.file("socket"), t.file("link-to-fifo"), t.file("link-to-file"),
                                   t.file("link-to-null"), t.file("no/such/folder/out"), std::string("/proc/icobrdf-out")}) {
      SCOPED_TRACE(out);
      const auto r = run_cli(with_output(args, out));
      EXPECT_EQ(r.exit_code, 5) << r.err;
      ASSERT_FALSE(r.err.empty());
      EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;  // one line
      EXPECT_NE(r.err.find(out), std::string::npos) << r.err;
      EXPECT_EQ(r.err.find("[1/"), std::string::npos) << "bank build fitted a material first: " << r.err;
      EXPECT_TRUE(r.out.empty()) << r.out;
    }
    // Every node as it was; no temporary, probe, resume file or report folder left.
    EXPECT_EQ(listing(t.path), before);
  }
}

// bank build -o FOLDER used to notice the folder only after fitting every material: now the scene is read,
// the outputs (the bank and its resume file) are checked, and nothing is fitted.
TEST_F(OutputPaths, BankBuildIntoAFolderFailsBeforeFittingAnything) {
  TempDir t;
  ASSERT_EQ(::mkdir(t.file("bank.h5").c_str(), 0755), 0);
  const auto r = run_cli({"bank", "build", scene(), "-o", t.file("bank.h5")});  // progress lines on
  EXPECT_EQ(r.exit_code, 5);
  EXPECT_EQ(r.err, "icobrdf: error: " + t.file("bank.h5") +
                       ": cannot write: the path is a folder, expected a regular file or a new file name\n");
  // The resume file is an output too: a folder or FIFO there would fail the first checkpoint, or be replaced.
  ASSERT_EQ(::rmdir(t.file("bank.h5").c_str()), 0);
  ASSERT_EQ(::mkfifo(t.file("bank.h5.partial").c_str(), 0644), 0);
  const std::string before = listing(t.path);
  const auto p = run_cli({"bank", "build", scene(), "-o", t.file("bank.h5")});
  EXPECT_EQ(p.exit_code, 5);
  EXPECT_NE(p.err.find(t.file("bank.h5.partial") + ": cannot write: the path is a FIFO"), std::string::npos) << p.err;
  EXPECT_EQ(p.err.find("[1/"), std::string::npos) << p.err;
  EXPECT_EQ(listing(t.path), before) << "nothing written, the FIFO kept";
}

TEST_F(OutputPaths, AnOutputThatIsOneOfTheInputsIsRefusedAndTheInputKept) {
  TempDir t;
  // A scene whose material comes from the bank it would be written over.
  std::ofstream(t.file("rebuild.toml")) << "[bank]\nlevels = [1]\norder_max = 2\n[[material]]\nname = \"a\"\nsource = \"" << bank()
                                        << "#a\"\n";
  ASSERT_EQ(::link(bank().c_str(), t.file("hard-link.h5").c_str()), 0);  // another name, the same file
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"bank", "extract", bank() + "#a", "-o", bank()}, bank()},  // the issue's example: 2 materials -> 1
      {{"bank", "extract", bank() + "#a", "-o", t.file("hard-link.h5")}, bank()},
      {{"bank", "build", scene(), "-o", scene()}, scene()},
      {{"bank", "build", t.file("rebuild.toml"), "-o", bank()}, bank()},
      {{"fit", spectrum(), "--order", "1", "--level", "1", "-o", spectrum()}, spectrum()},
      {{"lut", bank() + "#b", "--level", "1", "--order", "1", "-o", bank()}, bank()},
      {{"smooth", lut(), "--order", "1", "-o", lut()}, lut()},
      {{"export", spectrum(), "--format", "scatmech", "-o", spectrum()}, spectrum()},
      {{"plot", "spectrum", spectrum(), "-o", spectrum()}, spectrum()},
      {{"plot", "slice", spectrum(), "--order", "1", "-o", spectrum()}, spectrum()},
      {{"plot", "sphere", bank(), "--size", "16", "-o", bank()}, bank()},
  };
  for (const auto& [args, input] : cases) {
    SCOPED_TRACE(joined(args));
    const std::string before = slurp(input);
    const auto r = run_cli(args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    EXPECT_NE(r.err.find("is the same file as the input"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("[1/"), std::string::npos) << r.err;
    EXPECT_TRUE(slurp(input) == before) << input << " changed";
  }
  const auto info = run_cli({"bank", "info", bank(), "--json"});
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_EQ(nlohmann::json::parse(info.out)["materials"].size(), 2u);
}

}  // namespace
}  // namespace icobrdf::test
