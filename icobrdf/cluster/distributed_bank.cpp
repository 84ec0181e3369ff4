#include "icobrdf/cluster/distributed_bank.hpp"

#include <unistd.h>

#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <exception>
#include <fstream>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "icobrdf/core/error.hpp"
#include "icobrdf/io/bank_file.hpp"
#include "icobrdf/pipeline/bank_assembly.hpp"
#include "icobrdf/pipeline/bank_resume.hpp"

namespace icobrdf {
namespace {

// Message tags. kReport (rank r -> 0): a header and a payload; kWork (0 -> r): 8 bytes, the material's
// index; kDone (0 -> r): no more work.
constexpr int kReport = 1, kWork = 2, kDone = 3;

// Header of a report: the material's index (int64, -1 when the report carries no material: the first
// request), its outcome, and whether the rank asks for more work (0 when it was told to stop).
enum class Outcome : std::uint8_t { none = 0, finished = 1, failed = 2 };
constexpr std::size_t kHeaderBytes = 10;

std::string header(std::int64_t index, Outcome outcome, bool wants_more) {
  std::string h(kHeaderBytes, '\0');
  std::memcpy(h.data(), &index, 8);
  h[8] = static_cast<char>(outcome);
  h[9] = static_cast<char>(wants_more ? 1 : 0);
  return h;
}

std::int64_t index_of(const std::string& bytes) {
  std::int64_t i = -1;
  if (bytes.size() >= 8) std::memcpy(&i, bytes.data(), 8);
  return i;
}

// A private folder for the record files of this process, removed with its content.
class ScratchFolder {
 public:
  ScratchFolder() {
    const char* tmp = std::getenv("TMPDIR");
    std::string pattern = std::string(tmp && *tmp ? tmp : "/tmp") + "/icobrdf-mpi-XXXXXX";
    if (!::mkdtemp(pattern.data())) throw IoError("MPI bank build: cannot create a scratch folder " + pattern + ": " + std::strerror(errno));
    path_ = pattern;
  }
  ~ScratchFolder() {
    ::unlink(file().c_str());
    ::rmdir(path_.c_str());
  }
  std::string file() const { return path_ + "/record.h5"; }

 private:
  std::string path_;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  if (!in && !in.eof()) throw IoError(path + ": cannot be read back");
  return s.str();
}

// A record as the bytes of a one-material bank file (the resume file's format), and back.
std::string record_bytes(MaterialRecord record, const ScratchFolder& scratch) {
  BankContents one;
  one.materials.push_back(std::move(record));
  write_bank(scratch.file(), one);
  std::string bytes = slurp(scratch.file());
  ::unlink(scratch.file().c_str());
  return bytes;
}

MaterialRecord record_from_bytes(const char* data, std::size_t size, const ScratchFolder& scratch) {
  {
    std::ofstream out(scratch.file(), std::ios::binary | std::ios::trunc);
    out.write(data, static_cast<std::streamsize>(size));
    if (!out) throw IoError(scratch.file() + ": cannot be written");
  }
  BankContents one = read_bank(scratch.file());
  ::unlink(scratch.file().c_str());
  if (one.materials.size() != 1)
    throw InputError("MPI bank build: a result holds " + std::to_string(one.materials.size()) + " materials, expected 1");
  return std::move(one.materials.front());
}

std::string progress_line(const Scene& scene, std::size_t handed, std::size_t index, int rank) {
  const auto& m = scene.materials[index];
  return "[" + std::to_string(handed) + "/" + std::to_string(scene.materials.size()) + "] " + m.name + " (" + quoted_text(m.source) +
         ") on rank " + std::to_string(rank);
}

// Ranks other than 0: ask, fit, send, until rank 0 says done (or this rank was told to stop).
void serve(const Scene& scene, const BankBuildOptions& options, Cluster& cluster) {
  BankBuildOptions quiet = options;
  quiet.progress = nullptr;
  MaterialFitter fitter(scene, quiet);
  const ScratchFolder scratch;
  cluster.send(0, kReport, header(-1, Outcome::none, true));
  for (;;) {
    const Cluster::Message m = cluster.wait(0);
    if (m.tag != kWork) return;  // kDone
    const std::int64_t index = index_of(m.bytes);
    MaterialReport report = new_material_report(scene, static_cast<std::size_t>(index));
    Outcome outcome = Outcome::finished;
    std::string payload;
    try {
      payload = record_bytes(fitter.fit(static_cast<std::size_t>(index), report), scratch);
    } catch (const std::exception& e) {
      outcome = Outcome::failed;
      payload = e.what();
    }
    const bool more = !(options.stop && options.stop->load() != 0);
    cluster.send(0, kReport, header(index, outcome, more) + payload);
    if (!more) return;
  }
}

// Rank 0's shared state: the materials not yet handed out, who fits what, and the reports received.
struct Coordinator {
  Coordinator(const Scene& s, const BankBuildOptions& o, int ranks) : scene(s), options(o), fitting(static_cast<std::size_t>(ranks), -1) {}
  const Scene& scene;
  const BankBuildOptions& options;
  std::mutex lock;
  std::condition_variable arrived;
  std::deque<std::size_t> todo;                 // not yet handed out, in scene order
  std::size_t handed = 0;                       // handed out so far (resumed ones counted), for progress lines
  std::vector<std::int64_t> fitting;            // per rank: the index it fits, -1 when none
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
    fitting[static_cast<std::size_t>(rank)] = static_cast<std::int64_t>(i);
    const std::string line = progress_line(scene, ++handed, i, rank);
    g.unlock();
    say(line);
    return static_cast<std::int64_t>(i);
  }
  // "'b' on rank 1, 'a' on rank 0": what each rank is fitting.
  std::string in_progress() {
    std::lock_guard<std::mutex> g(lock);
    std::string s;
    for (std::size_t r = 0; r < fitting.size(); ++r) {
      if (fitting[r] < 0) continue;
      s += (s.empty() ? "" : ", ") + std::string("'") + scene.materials[static_cast<std::size_t>(fitting[r])].name + "' on rank " + std::to_string(r);
    }
    return s.empty() ? "no material" : s;
  }
};

// Rank 0's helper thread: the only one that calls MPI while the build runs.
void answer_requests(Coordinator& co, Cluster& cluster) {
  int active = cluster.size() - 1;
  bool told_stop = false;
  while (active > 0) {
    if (!told_stop && co.stopped()) {
      told_stop = true;
      const std::string line = "icobrdf: stopping on signal " + std::to_string(co.options.stop->load()) +
                               " (mpirun sends SIGTERM when a rank fails or is killed) while fitting " + co.in_progress() +
                               "; the bank is not written\n";
      (void)!::write(STDERR_FILENO, line.data(), line.size());
    }
    auto m = cluster.poll();
    if (!m) {
      std::this_thread::sleep_for(kPollInterval);
      continue;
    }
    if (m->tag != kReport || m->bytes.size() < kHeaderBytes) continue;
    const auto outcome = static_cast<Outcome>(m->bytes[8]);
    const bool more = m->bytes[9] != 0;
    {
      std::lock_guard<std::mutex> g(co.lock);
      co.fitting[static_cast<std::size_t>(m->source)] = -1;
      if (outcome != Outcome::none) co.inbox.push_back(*m);
    }
    if (outcome != Outcome::none) co.arrived.notify_all();
    if (!more) {
      --active;
      continue;
    }
    const std::int64_t next = co.take(m->source);
    if (next >= 0) {
      std::string bytes(8, '\0');
      std::memcpy(bytes.data(), &next, 8);
      cluster.send(m->source, kWork, bytes);
    } else {
      cluster.send(m->source, kDone, "");
      --active;
    }
  }
  {
    std::lock_guard<std::mutex> g(co.lock);
    co.helper_done = true;
  }
  co.arrived.notify_all();
}

// Rank 0's main thread: the reports received so far go to the collector.
void take_reports(Coordinator& co, BankCollector& out, const ScratchFolder& scratch) {
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
    const char* payload = m.bytes.data() + kHeaderBytes;
    const std::size_t size = m.bytes.size() - kHeaderBytes;
    if (static_cast<Outcome>(m.bytes[8]) == Outcome::failed) {
      out.failed(index, std::move(report), std::string(payload, size));
      continue;
    }
    MaterialRecord record;
    try {
      record = record_from_bytes(payload, size, scratch);
    } catch (const std::exception& e) {
      out.failed(index, std::move(report), std::string("its record from rank ") + std::to_string(m.source) + " could not be read: " + e.what());
      continue;
    }
    report_from_record(record, report);
    report.resumed = false;
    out.finished(index, std::move(record), std::move(report));
  }
}

BankBuildResult coordinate(const Scene& scene, const BankBuildOptions& options, Cluster& cluster, BankCollector& out) {
  Coordinator co(scene, options, cluster.size());
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    if (out.take_resumed(i))
      ++co.handed;
    else
      co.todo.push_back(i);
  }
  std::thread helper([&co, &cluster] { answer_requests(co, cluster); });
  std::exception_ptr error;
  bool interrupted = false;
  // Made after the helper started, so that the other ranks are answered (told done) whatever happens here.
  std::optional<MaterialFitter> fitter;
  std::optional<ScratchFolder> scratch;
  try {
    fitter.emplace(scene, options);
    scratch.emplace();
    for (;;) {
      take_reports(co, out, *scratch);
      if (co.stopped()) {
        interrupted = true;
        break;
      }
      const std::int64_t i = co.take(0);
      if (i < 0) break;
      MaterialReport report = new_material_report(scene, static_cast<std::size_t>(i));
      report.rank = 0;
      try {
        MaterialRecord record = fitter->fit(static_cast<std::size_t>(i), report);
        {
          std::lock_guard<std::mutex> g(co.lock);
          co.fitting[0] = -1;
        }
        out.finished(static_cast<std::size_t>(i), std::move(record), std::move(report));
      } catch (const std::exception& e) {
        {
          std::lock_guard<std::mutex> g(co.lock);
          co.fitting[0] = -1;
        }
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
    co.arrived.wait(g, [&co] { return co.helper_done || !co.inbox.empty(); });
    const bool finished = co.helper_done && co.inbox.empty();
    g.unlock();
    if (finished) break;
    if (!error) try {
        take_reports(co, out, *scratch);
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

}  // namespace icobrdf
