#include "icobrdf/io/atomic_write.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <mutex>
#include <set>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/output_path.hpp"

namespace icobrdf {

namespace {

std::function<void(const std::string&)>& fault_hook() {
  static std::function<void(const std::string&)> hook;
  return hook;
}

[[noreturn]] void fail(const std::string& path, const std::string& what, int err) {
  throw IoError(path + ": cannot write: " + what + ": " + std::strerror(err));
}

// fsync of a file or folder by path; returns 0 or an errno value.
int sync_path(const std::string& p, bool folder) {
  const int fd = ::open(p.c_str(), (folder ? O_RDONLY | O_DIRECTORY : O_RDWR) | O_CLOEXEC);
  if (fd < 0) return errno;
  int err = 0;
  if (::fsync(fd) != 0) err = errno;
  // Some file systems cannot fsync a folder (EINVAL); the rename is then as durable as they allow.
  if (folder && err == EINVAL) err = 0;
  if (::close(fd) != 0 && err == 0) err = errno;
  return err;
}

// Temporaries of the atomic writes in progress (remove_unfinished_temporaries).
std::mutex& temporaries_mutex() {
  static std::mutex m;
  return m;
}
std::set<std::string>& temporaries() {
  static std::set<std::string> t;
  return t;
}

// The same names in fixed slots that a signal handler may read (no lock, no allocation): a slot is claimed
// (free -> filling), its name copied, then published (-> held); a name too long for a slot, or beyond the
// last slot, is only in the set above (the signal path then leaves it; no write of ours holds 64 at once).
constexpr int kSignalSlots = 64;
constexpr std::size_t kSlotPath = 4096;
enum SlotState : int { kFree = 0, kFilling = 1, kHeld = 2 };
struct SignalSlot {
  std::atomic<int> state{kFree};
  char path[kSlotPath];
};
SignalSlot g_slots[kSignalSlots];

void hold_in_slot(const std::string& p) {
  if (p.size() >= kSlotPath) return;
  for (auto& slot : g_slots) {
    int expected = kFree;
    if (!slot.state.compare_exchange_strong(expected, kFilling)) continue;
    std::memcpy(slot.path, p.c_str(), p.size() + 1);
    slot.state.store(kHeld, std::memory_order_release);
    return;
  }
}

void release_slot(const std::string& p) {
  for (auto& slot : g_slots)
    if (slot.state.load(std::memory_order_acquire) == kHeld && p == slot.path) {
      slot.state.store(kFree, std::memory_order_release);
      return;
    }
}

}  // namespace

void remove_unfinished_temporaries() {
  std::lock_guard<std::mutex> lock(temporaries_mutex());
  for (const auto& t : temporaries()) {
    ::unlink(t.c_str());
    release_slot(t);
  }
  temporaries().clear();
}

int remove_unfinished_temporaries_in_signal_handler() {
  int removed = 0;
  for (auto& slot : g_slots)
    if (slot.state.load(std::memory_order_acquire) == kHeld && ::unlink(slot.path) == 0) ++removed;
  return removed;
}

std::string file_name(const std::string& path) {
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

std::string parent_folder(const std::string& path) {
  const auto slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

void set_write_fault_hook(std::function<void(const std::string& point)> hook) { fault_hook() = std::move(hook); }

void write_fault_point(const std::string& point) {
  if (fault_hook()) fault_hook()(point);
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)) {
  check_output_target(path_);  // a regular file or a new name in an existing folder
  const std::string name = file_name(path_), folder = parent_folder(path_);
  static std::atomic<unsigned> counter{0};
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    temp_ = folder + "/." + name + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
    // Held before it exists, so that a stop signal arriving just after the open still removes it (a name with
    // our pid that exists already is a stale temporary of a dead process of the same pid).
    hold_in_slot(temp_);
    fd = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) {
      const int err = errno;
      release_slot(temp_);
      if (err != EEXIST) fail(path_, "cannot create a temporary in " + folder, err);
    }
  }
  if (fd < 0) fail(path_, "cannot find a free temporary name in " + folder, EEXIST);
  ::close(fd);
  std::lock_guard<std::mutex> lock(temporaries_mutex());
  temporaries().insert(temp_);
}

AtomicFile::~AtomicFile() {
  if (!committed_) ::unlink(temp_.c_str());
  std::lock_guard<std::mutex> lock(temporaries_mutex());
  if (temporaries().erase(temp_) > 0) release_slot(temp_);
}

void AtomicFile::commit() {
  write_fault_point("atomic_write:produced");
  if (const int err = sync_path(temp_, false)) fail(path_, "fsync of the temporary " + temp_, err);
  write_fault_point("atomic_write:synced");
  check_output_target(path_);  // again: the path may have changed while the temporary was written
  if (::rename(temp_.c_str(), path_.c_str()) != 0) fail(path_, "rename of the temporary " + temp_, errno);
  committed_ = true;
  const std::string folder = parent_folder(path_);
  if (const int err = sync_path(folder, true))
    throw IoError(path_ + ": written, but the fsync of its folder " + folder + " failed: " + std::strerror(err));
}

void atomic_write(const std::string& path, const std::function<void(const std::string& temp_path)>& produce) {
  AtomicFile file(path);
  produce(file.temp_path());
  file.commit();
}

void atomic_write_bytes(const std::string& path, const void* data, std::size_t size) {
  atomic_write(path, [&](const std::string& temp) {
    const int fd = ::open(temp.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) fail(path, "open its temporary", errno);
    const char* at = static_cast<const char*>(data);
    std::size_t left = size;
    while (left > 0) {
      const ssize_t n = ::write(fd, at, left);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        const int err = n < 0 ? errno : EIO;
        ::close(fd);
        fail(path, "write to its temporary", err);
      }
      at += n;
      left -= static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0) fail(path, "close its temporary", errno);
  });
}

void atomic_write_text(const std::string& path, const std::string& text) { atomic_write_bytes(path, text.data(), text.size()); }

}  // namespace icobrdf
