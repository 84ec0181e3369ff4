// Several materials fitted at once in one process (icobrdf/pipeline/bank_builder.hpp, plan_materials_at_once):
// the plan, and builds with W = 2 fitting threads against the same build one material at a time. The
// bank-file identity across thread counts is tested end to end in tests/cli/test_bank_threads.cpp.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <mutex>
#include <set>
#include <string>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/io/spectrum_file.hpp"
#include "icobrdf/pipeline/bank_builder.hpp"
#include "tests/io/io_test_support.hpp"
#include "tests/support/unity_id.hpp"

namespace icobrdf {
namespace ICOBRDF_UNITY_ID {

SceneMaterial material(const std::string& name, const std::string& source, int level, double target = 100.0) {
  SceneMaterial m;
  m.name = name;
  m.source = source;
  m.level = level;
  m.order = 4;
  m.target = target;
  return m;
}

// Level 2-3 fits of a few milliseconds each; modes only, so that every material is fitted the same way.
Scene small_scene(int materials) {
  Scene s;
  s.level = 3;
  s.levels = {2, 3};
  s.order_max = 4;
  s.holdout_pairs = 64;
  s.representations = {"modes"};
  const char* sources[] = {"model:lambert:albedo=0.5", "model:ggx:alpha=0.5", "model:oren-nayar:sigma=20,albedo=0.7",
                           "model:phong:n=5", "model:ggx-aniso:alpha_x=0.3,alpha_y=0.6,azimuth=30"};
  for (int i = 0; i < materials; ++i) s.materials.push_back(material("m" + std::to_string(i), sources[i % 5], 2 + i % 2));
  return s;
}

// OpenMP's thread count for this thread while in scope (the plan reads omp_get_max_threads).
struct Threads {
  int previous = omp_get_max_threads();
  explicit Threads(int n) { omp_set_num_threads(n); }
  ~Threads() { omp_set_num_threads(previous); }
};

std::vector<std::size_t> all(const Scene& s) {
  std::vector<std::size_t> v(s.materials.size());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = i;
  return v;
}

TEST(MaterialsAtOnce, PlanFitsSmallGridsAtOnceAndLargeOnesAloneFirst) {
  Scene s = small_scene(3);
  s.levels = {3, 4};
  s.materials.push_back(material("large", "model:lambert", 5));  // 10,304 cells > kConcurrentFitMaxCells
  SceneMaterial search = material("search", "model:lambert", -1);  // searches the levels: sized by the largest, 4
  s.materials.push_back(search);
  const MaterialsAtOnce p = plan_materials_at_once(s, all(s), 2, 0);
  EXPECT_EQ(p.workers, 2);
  EXPECT_EQ(p.threads_each, 1);
  EXPECT_EQ(p.alone, (std::vector<std::size_t>{3}));
  EXPECT_EQ(p.at_once, (std::vector<std::size_t>{0, 1, 2, 4}));
  // The same search up to level 5 is large.
  s.levels = {3, 4, 5};
  EXPECT_EQ(plan_materials_at_once(s, all(s), 2, 0).alone, (std::vector<std::size_t>{3, 4}));
}

TEST(MaterialsAtOnce, PlanFollowsTheThreadsAndTheRequest) {
  const Scene s = small_scene(4);
  const auto one_at_a_time = [](const MaterialsAtOnce& p, int threads) {
    return p.workers == 1 && p.threads_each == threads && p.at_once.empty() && p.alone == std::vector<std::size_t>{0, 1, 2, 3};
  };
  EXPECT_TRUE(one_at_a_time(plan_materials_at_once(s, all(s), 1, 0), 1));  // one thread: nothing to share
  EXPECT_TRUE(one_at_a_time(plan_materials_at_once(s, all(s), 2, 1), 2));  // asked for one at a time
  const MaterialsAtOnce four = plan_materials_at_once(s, all(s), 8, 0);  // one thread each, as many as materials
  EXPECT_EQ(four.workers, 4);
  EXPECT_EQ(four.threads_each, 2);
  const MaterialsAtOnce two = plan_materials_at_once(s, all(s), 8, 2);  // asked for 2 on 8 threads: 4 each
  EXPECT_EQ(two.workers, 2);
  EXPECT_EQ(two.threads_each, 4);
  // A single small material has nothing to share its threads with.
  const MaterialsAtOnce single = plan_materials_at_once(s, {2}, 2, 0);
  EXPECT_EQ(single.workers, 1);
  EXPECT_EQ(single.threads_each, 2);
  EXPECT_EQ(single.alone, std::vector<std::size_t>{2});
  EXPECT_TRUE(single.at_once.empty());
  EXPECT_THROW(plan_materials_at_once(s, all(s), 2, -1), ArgumentError);
}

struct Build {
  BankBuildResult result;
  std::vector<std::string> started;  // the progress lines "[k/N] name (...)"
};

Build build(const Scene& scene, const std::string& output, int at_once, std::atomic<int>* stop = nullptr, int stop_after = 0) {
  Build b;
  std::mutex lines;
  BankBuildOptions opt;
  opt.output = output;
  opt.materials_at_once = at_once;
  opt.stop = stop;
  opt.progress = [&](const std::string& line) {
    std::lock_guard<std::mutex> g(lines);
    if (line.empty() || line[0] != '[') return;
    b.started.push_back(line);
    if (stop && static_cast<int>(b.started.size()) == stop_after) stop->store(15);
  };
  b.result = build_bank(scene, opt);
  return b;
}

// Each material's progress line once, numbered 1..N in the order they started.
void expect_each_started_once(const Build& b, const Scene& s) {
  std::set<std::string> names;
  for (std::size_t k = 0; k < b.started.size(); ++k) {
    const std::string& line = b.started[k];
    const std::string number = "[" + std::to_string(k + 1) + "/" + std::to_string(s.materials.size()) + "] ";
    ASSERT_EQ(line.rfind(number, 0), 0u) << line;
    names.insert(line.substr(number.size(), line.find(' ', number.size()) - number.size()));
  }
  EXPECT_EQ(names.size(), b.started.size());
}

TEST(MaterialsAtOnce, TwoAtOnceGiveTheRecordsOfOneAtATimeInSceneOrder) {
  const Threads two(2);
  const Scene s = small_scene(7);
  icobrdf::test::ScratchDir dir;
  const Build serial = build(s, dir / "serial.h5", 1), at_once = build(s, dir / "at_once.h5", 2);
  ASSERT_TRUE(serial.result.written);
  ASSERT_TRUE(at_once.result.written);
  expect_each_started_once(at_once, s);
  EXPECT_EQ(at_once.started.size(), 7u);
  const BankContents a = read_bank(dir / "serial.h5"), b = read_bank(dir / "at_once.h5");
  ASSERT_EQ(a.materials.size(), 7u);
  ASSERT_EQ(b.materials.size(), 7u);
  for (std::size_t i = 0; i < 7; ++i) {
    const MaterialRecord &x = a.materials[i], &y = b.materials[i];
    EXPECT_EQ(y.name, "m" + std::to_string(i));  // scene order, whatever order they finished in
    EXPECT_EQ(at_once.result.materials[i].name, y.name);
    ASSERT_EQ(x.spectrum.channels.size(), y.spectrum.channels.size());
    for (std::size_t c = 0; c < x.spectrum.channels.size(); ++c)
      EXPECT_EQ(x.spectrum.channels[c], y.spectrum.channels[c]) << y.name;  // bit for bit: a fit does not depend on its threads
    EXPECT_EQ(x.figures.at("fit_level"), y.figures.at("fit_level"));
    EXPECT_EQ(x.figures.at("error_l2"), y.figures.at("error_l2"));
  }
}

TEST(MaterialsAtOnce, AFailedMaterialFailsTheBuildAndTheOthersAreKeptForResume) {
  const Threads two(2);
  Scene s = small_scene(5);
  s.materials[2].target = 1e-12;  // an order-4 fit of Oren-Nayar cannot reach it: this material fails
  icobrdf::test::ScratchDir dir;
  const Build b = build(s, dir / "bank.h5", 2);
  EXPECT_FALSE(b.result.written);
  ASSERT_EQ(b.result.materials.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(b.result.materials[i].ok, i != 2) << b.result.materials[i].name << ": " << b.result.materials[i].error;
  EXPECT_NE(b.result.materials[2].error.find("target"), std::string::npos) << b.result.materials[2].error;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"bank.h5.partial"});
  EXPECT_EQ(read_bank(dir / "bank.h5.partial").materials.size(), 4u);
}

TEST(MaterialsAtOnce, AStopStartsNoFurtherMaterialAndKeepsTheFinishedOnes) {
  const Threads two(2);
  const Scene s = small_scene(6);
  icobrdf::test::ScratchDir dir;
  std::atomic<int> stop{0};
  const Build b = build(s, dir / "bank.h5", 2, &stop, 2);  // the stop comes as the second material starts
  EXPECT_TRUE(b.result.interrupted);
  EXPECT_FALSE(b.result.written);
  EXPECT_EQ(b.started.size(), 2u);
  EXPECT_EQ(b.result.materials.size(), 2u);  // the two started ones finished
  EXPECT_EQ(read_bank(dir / "bank.h5.partial").materials.size(), 2u);
  // --resume takes them and fits the other four.
  stop = 0;
  BankBuildOptions opt;
  opt.output = dir / "bank.h5";
  opt.resume = true;
  opt.materials_at_once = 2;
  const BankBuildResult again = build_bank(s, opt);
  EXPECT_TRUE(again.written);
  int resumed = 0;
  for (const auto& m : again.materials) resumed += m.resumed;
  EXPECT_EQ(resumed, 2);
  EXPECT_EQ(read_bank(dir / "bank.h5").materials.size(), 6u);
}

}  // namespace ICOBRDF_UNITY_ID
}  // namespace icobrdf
