#pragma once
// Atomic file replacement: readers of `path` only ever see the previous file or the complete new one.
//
// atomic_write(path, produce):
//   1. refuses (IoError) what check_output_target (icobrdf/io/output_path.hpp) refuses: a path that exists and is
//      not a regular file (folder, FIFO, device, socket, symbolic link), or whose folder is missing / not a
//      folder; it checks again just before the rename, so no writer ever replaces a device or a link;
//   2. creates a new temporary "<folder>/.<name>.tmp-<pid>-<n>" with O_CREAT | O_EXCL (mode 0666 & ~umask),
//      in the same folder so the final rename stays on one file system;
//   3. calls produce(temp_path), which writes the whole content there;
//   4. fsyncs the temporary, renames it over `path`, fsyncs the folder.
// Any failure in steps 2-4 (an exception from produce included) removes the temporary and leaves an
// existing file at `path` untouched; file-system failures throw IoError naming `path`, exceptions from
// produce propagate unchanged. `path` itself is never opened, let alone truncated: only rename() touches it.
// A crash (power loss, SIGKILL) can leave a stale ".<name>.tmp-*" beside `path`, never a partial `path`.
#include <cstddef>
#include <functional>
#include <string>

namespace icobrdf {

void atomic_write(const std::string& path, const std::function<void(const std::string& temp_path)>& produce);

// atomic_write's steps as an object, for a file written over a longer time (a bank written as its materials
// are fitted, icobrdf/io/bank_file.hpp BankWriter): the constructor takes steps 1-2, the caller writes to
// temp_path(), commit() takes step 4. Destroyed without commit() (an exception, an interrupted build), it
// removes the temporary and leaves `path` untouched. Failures as atomic_write's.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  const std::string& temp_path() const { return temp_; }
  void commit();

 private:
  std::string path_, temp_;
  bool committed_ = false;
};

// Removes the temporaries of atomic writes still in progress in this process: for a program that must end
// at once (std::terminate after an allocation failed in a worker thread), so that it leaves no partial output.
// Files already renamed into place are untouched.
void remove_unfinished_temporaries();

// The same from a signal handler: async-signal-safe (reads fixed slots, calls only unlink); the registry is
// left as it is, since the program ends next (icobrdf/io/program_end.hpp).
int remove_unfinished_temporaries_in_signal_handler();  // how many were removed

// atomic_write of `size` bytes (or a text) as the whole file. A failed write (full disk, file-size limit)
// throws IoError "PATH: cannot write: write to its temporary: <the system's reason>".
void atomic_write_bytes(const std::string& path, const void* data, std::size_t size);
void atomic_write_text(const std::string& path, const std::string& text);

// The folder holding `path` ("." for a bare name), and the name in it (after the last '/').
std::string parent_folder(const std::string& path);
std::string file_name(const std::string& path);

// Test hook for fault injection: when set, atomic_write and the file writers call it at named points
// ("atomic_write:produced" after produce returns, "atomic_write:synced" just before the rename, and the
// points the writers document); throwing from it simulates a failure there. Pass an empty function to clear.
void set_write_fault_hook(std::function<void(const std::string& point)> hook);
void write_fault_point(const std::string& point);

}  // namespace icobrdf
