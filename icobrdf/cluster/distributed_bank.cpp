#include "icobrdf/cluster/distributed_bank.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <deque>
#include <exception>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/atomic_write.hpp"
#include "icobrdf/io/record_wire.hpp"
#include "icobrdf/io/scene.hpp"
#include "icobrdf/pipeline/bank_assembly.hpp"
#include "icobrdf/pipeline/bank_resume.hpp"

namespace icobrdf {
namespace {

// Message tags. kReport (rank r -> 0): a header and a payload; kWork (0 -> r): 8 bytes, the material's
// index; kDone (0 -> r): no more work.
constexpr int kReport = 1, kWork = 2, kDone = 3;

// Header of a report: the material's index (int64, -1 when the report carries no material: the first
// request), its outcome, whether the rank stays (0 once it was told done or to stop), and how many more
// materials it asks for with this report (0-255; each is answered by a kWork or a kDone).
// `returned`: a material handed out but not fitted (the rank was stopped); rank 0 hands it out again.
enum class Outcome : std::uint8_t { none = 0, finished = 1, failed = 2, returned = 3 };
constexpr std::size_t kHeaderBytes = 11;
// How often rank 0's main thread, waiting for the other ranks' last materials, looks for a stop.
constexpr std::chrono::milliseconds kStopCheck{20};

std::string header(std::int64_t index, Outcome outcome, bool stays, int asks) {
  std::string h(kHeaderBytes, '\0');
  std::memcpy(h.data(), &index, 8);
  h[8] = static_cast<char>(outcome);
  h[9] = static_cast<char>(stays ? 1 : 0);
  h[10] = static_cast<char>(static_cast<std::uint8_t>(asks));
  return h;
}

std::int64_t index_of(const std::string& bytes) {
  std::int64_t i = -1;
  if (bytes.size() >= 8) std::memcpy(&i, bytes.data(), 8);
  return i;
}

std::string progress_line(const Scene& scene, std::size_t handed, std::size_t index, int rank) {
  const auto& m = scene.materials[index];
  return "[" + std::to_string(handed) + "/" + std::to_string(scene.materials.size()) + "] " + m.name + " (" + quoted_text(m.source) +
         ") on rank " + std::to_string(rank);
}

// Ranks other than 0: ask, fit, send, until rank 0 says done (or this rank was told to stop). Every report
// asks for as many materials as keep 1 + materials_ahead(mean fitting time) held or asked for; each ask is
// answered by a kWork or a kDone. The rank ends when it holds no material and every ask was answered.
void serve(const Scene& scene, const BankBuildOptions& options, Cluster& cluster) {
  BankBuildOptions quiet = options;
  quiet.progress = nullptr;
  MaterialFitter fitter(scene, quiet);
  std::deque<std::int64_t> held;  // handed to this rank, not yet reported
  int asked = 0;                  // asks not yet answered
  bool done = false;              // told done, or stopped
  double fit_seconds = 0.0;       // spent fitting so far
  int fitted = 0;
  const auto asks = [&] {
    if (done) return 0;
    const int want = 1 + materials_ahead(fitted > 0 ? fit_seconds / fitted : 0.0);
    return std::max(0, want - static_cast<int>(held.size()) - asked);
  };
  asked = asks();
  cluster.post(0, kReport, header(-1, Outcome::none, true, asked));
  for (;;) {
    while (asked > 0) {  // the answers so far; wait for one only when nothing is held
      auto m = held.empty() ? std::optional<Cluster::Message>(cluster.wait(0)) : cluster.poll(0);
      if (!m) break;
      --asked;
      if (m->tag == kWork)
        held.push_back(index_of(m->bytes));
      else
        done = true;
    }
    if (held.empty()) break;  // and asked == 0
    const std::int64_t index = held.front();
    held.pop_front();
    done = done || (options.stop && options.stop->load() != 0);
    Outcome outcome = Outcome::finished;
    std::string payload;
    if (options.stop && options.stop->load() != 0) {
      outcome = Outcome::returned;
    } else {
      MaterialReport report = new_material_report(scene, static_cast<std::size_t>(index));
      const auto t0 = std::chrono::steady_clock::now();
      try {
        payload = record_wire(fitter.fit(static_cast<std::size_t>(index), report));
      } catch (const std::exception& e) {
        outcome = Outcome::failed;
        payload = e.what();
      }
      fit_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      ++fitted;
    }
    const int more = asks();
    cluster.post(0, kReport, header(index, outcome, !done, more) + payload);
    asked += more;
  }
  cluster.finish_sends();
}

// Rank 0's shared state: the materials not yet handed out, who fits what, and the reports received.
struct Coordinator {
  Coordinator(const Scene& s, const BankBuildOptions& o, int ranks) : scene(s), options(o), held(static_cast<std::size_t>(ranks)) {}
  const Scene& scene;
  const BankBuildOptions& options;
  std::mutex lock;
  std::condition_variable arrived;
  std::deque<std::size_t> todo;                 // not yet handed out, in scene order
  std::size_t handed = 0;                       // handed out so far (resumed ones counted), for progress lines
  std::vector<std::deque<std::int64_t>> held;   // per rank: handed out, not yet reported (the first is being fitted)
  std::deque<Cluster::Message> inbox;           // reports with a material, for the main thread
  bool closing = false;                         // hand out nothing more (stop, or an error on rank 0)
  bool helper_done = false;                     // every other rank was told done

  void say(const std::string& line) {
    if (options.progress) options.progress(line);  // serialized by build_bank_distributed
  }
  bool stopped() const { return options.stop && options.stop->load() != 0; }
  // The next index for `rank`, or -1; with its progress line.
  std::int64_t take(int rank) {
    std::unique_lock<std::mutex> g(lock);
    if (closing || stopped() || todo.empty()) return -1;
    const std::size_t i = todo.front();
    todo.pop_front();
    held[static_cast<std::size_t>(rank)].push_back(static_cast<std::int64_t>(i));
    const std::string line = progress_line(scene, ++handed, i, rank);
    g.unlock();
    say(line);
    return static_cast<std::int64_t>(i);
  }
  // "'b' on rank 1, 'a' on rank 0": what each rank is fitting.
  std::string in_progress() {
    std::lock_guard<std::mutex> g(lock);
    std::string s;
    for (std::size_t r = 0; r < held.size(); ++r) {
      if (held[r].empty()) continue;
      s += (s.empty() ? "" : ", ") + std::string("'") + scene.materials[static_cast<std::size_t>(held[r].front())].name + "' on rank " + std::to_string(r);
    }
    return s.empty() ? "no material" : s;
  }
  // Material `index` reported by `rank`: no longer held; a returned one goes back to the front of the queue.
  void reported(int rank, std::int64_t index, bool returned) {
    std::lock_guard<std::mutex> g(lock);
    auto& h = held[static_cast<std::size_t>(rank)];
    for (auto it = h.begin(); it != h.end(); ++it)
      if (*it == index) {
        h.erase(it);
        break;
      }
    if (returned) {
      todo.push_front(static_cast<std::size_t>(index));
      --handed;
    }
  }
  bool holds(int rank) {
    std::lock_guard<std::mutex> g(lock);
    return !held[static_cast<std::size_t>(rank)].empty();
  }
  // Once stopped (mpirun sends SIGTERM when a rank fails or is killed): one line naming each rank's
  // material, and the bank's temporary removed at once, by whichever of rank 0's threads sees the stop first.
  // mpirun kills this rank too if it does not end soon, and it may not: the helper can be held inside MPI by
  // a transfer from the dead rank (OpenMPI's shared-memory read of a report fails when its sender dies
  // during it), and the main thread waits for the helper. So no partial file is left beside the output
  // whichever thread is held; the main thread's later removal finds nothing to do. Call without `lock`.
  void say_stopping() {
    std::call_once(stop_said, [this] {
      const std::string line = "icobrdf: stopping on signal " + std::to_string(options.stop->load()) +
                               " (mpirun sends SIGTERM when a rank fails or is killed) while fitting " + in_progress() +
                               "; the bank is not written\n";
      (void)!::write(STDERR_FILENO, line.data(), line.size());
      remove_unfinished_temporaries();
    });
  }
  std::once_flag stop_said;
};

// Rank 0's helper thread: the only one that calls MPI while the build runs. It answers every request at once;
// a rank is finished once it holds no material and was told done or said it stops (stays = 0): its
// first request came before any material, so every request it made was answered by then.
void answer_requests(Coordinator& co, Cluster& cluster) {
  const auto ranks = static_cast<std::size_t>(cluster.size());
  std::vector<char> told_done(ranks, 0), leaving(ranks, 0);
  const auto finished = [&](std::size_t r) { return (told_done[r] || leaving[r]) && !co.holds(static_cast<int>(r)); };
  const auto all_finished = [&] {
    for (std::size_t r = 1; r < ranks; ++r)
      if (!finished(r)) return false;
    return true;
  };
  while (!all_finished()) {
    if (co.stopped()) co.say_stopping();
    auto m = cluster.poll();
    if (!m) {
      std::this_thread::sleep_for(kPollInterval);
      continue;
    }
    if (m->tag != kReport || m->bytes.size() < kHeaderBytes) continue;
    const auto source = static_cast<std::size_t>(m->source);
    const auto outcome = static_cast<Outcome>(m->bytes[8]);
    const bool stays = m->bytes[9] != 0;
    const int asks = static_cast<std::uint8_t>(m->bytes[10]);
    if (!stays) leaving[source] = 1;
    if (outcome != Outcome::none) {
      co.reported(m->source, index_of(m->bytes), outcome == Outcome::returned);
      if (outcome != Outcome::returned) {
        {
          std::lock_guard<std::mutex> g(co.lock);
          co.inbox.push_back(std::move(*m));
        }
        co.arrived.notify_all();
      }
    }
    for (int k = 0; k < asks; ++k) {
      const std::int64_t next = co.take(static_cast<int>(source));
      if (next >= 0) {
        std::string bytes(8, '\0');
        std::memcpy(bytes.data(), &next, 8);
        cluster.send(static_cast<int>(source), kWork, bytes);
      } else {
        cluster.send(static_cast<int>(source), kDone, "");
        told_done[source] = 1;
      }
    }
  }
  {
    std::lock_guard<std::mutex> g(co.lock);
    co.helper_done = true;
  }
  co.arrived.notify_all();
}

// Rank 0's main thread: the reports received so far go to the collector.
void take_reports(Coordinator& co, BankCollector& out) {
  for (;;) {
    Cluster::Message m;
    {
      std::lock_guard<std::mutex> g(co.lock);
      if (co.inbox.empty()) return;
      m = std::move(co.inbox.front());
      co.inbox.pop_front();
    }
    const auto index = static_cast<std::size_t>(index_of(m.bytes));
    MaterialReport report = new_material_report(co.scene, index);
    report.rank = m.source;
    const std::string payload = m.bytes.substr(kHeaderBytes);
    if (static_cast<Outcome>(m.bytes[8]) == Outcome::failed) {
      out.failed(index, std::move(report), payload);
      continue;
    }
    MaterialRecord record;
    try {
      record = read_record_wire(payload, "record of material '" + report.name + "' from rank " + std::to_string(m.source));
    } catch (const std::exception& e) {
      out.failed(index, std::move(report), e.what());
      continue;
    }
    report_from_record(record, report);
    report.resumed = false;
    out.finished(index, std::move(record), std::move(report));
  }
}

BankBuildResult coordinate(const Scene& scene, const BankBuildOptions& options, Cluster& cluster, BankCollector& out) {
  Coordinator co(scene, options, cluster.size());
  std::exception_ptr error;
  try {  // taking a resumed material may write the resume file
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
      if (out.take_resumed(i))
        ++co.handed;
      else
        co.todo.push_back(i);
    }
  } catch (...) {
    error = std::current_exception();
    co.closing = true;  // the helper tells every rank done
  }
  std::thread helper([&co, &cluster] { answer_requests(co, cluster); });
  bool interrupted = false;
  // Made after the helper started, so that the other ranks are answered (told done) whatever happens here.
  std::optional<MaterialFitter> fitter;
  if (!error) try {
    fitter.emplace(scene, options);
    for (;;) {
      take_reports(co, out);
      if (co.stopped()) {
        co.say_stopping();
        interrupted = true;
        break;
      }
      const std::int64_t i = co.take(0);
      if (i < 0) break;
      MaterialReport report = new_material_report(scene, static_cast<std::size_t>(i));
      report.rank = 0;
      try {
        MaterialRecord record = fitter->fit(static_cast<std::size_t>(i), report);
        co.reported(0, i, false);
        out.finished(static_cast<std::size_t>(i), std::move(record), std::move(report));
      } catch (const std::exception& e) {
        co.reported(0, i, false);
        out.failed(static_cast<std::size_t>(i), std::move(report), e.what());
      }
    }
  } catch (...) {
    error = std::current_exception();
  }
  {
    std::lock_guard<std::mutex> g(co.lock);
    if (error || interrupted) co.closing = true;
  }
  // The other ranks' last materials: wait for them (and keep them, even after an error, for --resume).
  for (;;) {
    std::unique_lock<std::mutex> g(co.lock);
    co.arrived.wait_for(g, kStopCheck, [&co] { return co.helper_done || !co.inbox.empty(); });
    const bool finished = co.helper_done && co.inbox.empty();
    g.unlock();
    if (finished) break;
    if (co.stopped()) co.say_stopping();
    if (!error) try {
        take_reports(co, out);
      } catch (...) {
        error = std::current_exception();
      }
    else {
      std::lock_guard<std::mutex> g2(co.lock);
      co.inbox.clear();
    }
  }
  helper.join();
  if (error) std::rethrow_exception(error);
  interrupted = interrupted || co.stopped();
  return out.finish(fitter->operators(), interrupted);
}

}  // namespace

DistributedBankResult build_bank_distributed(const Scene& scene, const BankBuildOptions& options, Cluster& cluster) {
  DistributedBankResult result;
  if (cluster.rank() != 0) {
    result.worker = true;
    if (cluster.first_failed(true) >= 0) return result;  // rank 0 could not start the build
    serve(scene, options, cluster);
    return result;
  }
  // Progress lines come from both threads of rank 0: one at a time.
  BankBuildOptions serialized = options;
  if (options.progress) {
    auto lock = std::make_shared<std::mutex>();
    serialized.progress = [lock, say = options.progress](const std::string& line) {
      std::lock_guard<std::mutex> g(*lock);
      say(line);
    };
  }
  // Rank 0 checks the output paths and reads the resume file before any rank starts.
  std::unique_ptr<BankCollector> out;
  std::exception_ptr error;
  try {
    out = std::make_unique<BankCollector>(scene, serialized);
  } catch (...) {
    error = std::current_exception();
  }
  cluster.first_failed(!error);
  if (error) std::rethrow_exception(error);
  result.build = coordinate(scene, serialized, cluster, *out);
  return result;
}

std::optional<Scene> read_scene_on_every_rank(const std::string& path, Cluster& cluster) {
  Scene scene;
  std::exception_ptr error;
  try {
    scene = read_scene(path);
  } catch (...) {
    error = std::current_exception();
  }
  const int failed = cluster.first_failed(!error);
  if (error) std::rethrow_exception(error);
  if (failed >= 0 && cluster.rank() == 0)
    throw InputError(fmt::format("{}: rank {} could not read the scene (see its message)", path, failed));
  if (failed >= 0) return std::nullopt;
  return scene;
}

}  // namespace icobrdf
