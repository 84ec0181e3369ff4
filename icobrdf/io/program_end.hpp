#pragma once
// How a program of this library ends, whatever the command: a stop signal leaves no partial output, and a
// failed write of the standard output is an error, not exit 0.
//
// - guard_standard_streams(): at start. A descriptor 0, 1 or 2 that is closed is opened on /dev/null (input)
//   or /dev/full (outputs), so that no file the program opens later takes its number (the lines meant for
//   the standard output would go into that file); a write to a closed standard output then fails, and
//   finish_standard_output says the stream was closed.
// - install_stop_signals(): SIGINT and SIGTERM remove the temporaries of unfinished atomic writes
//   (icobrdf/io/atomic_write.hpp), write one line when they removed any, and end the process with 128 + the
//   signal (130, 143).
//   Files already renamed into place stay. A command that stops cleanly on its own (bank build keeps its
//   finished materials) installs its own handler over this one. SIGXFSZ is ignored (a write over the
//   file-size limit fails as on a full disk), and HDF5's exit handler is not registered
//   (h5::leave_library_at_exit).
// - record_stop_signals(): for a command that stops cleanly on its own: SIGINT and SIGTERM from then on only
//   store the signal's number in the returned flag (0 until one came), which the work polls.
// - finish_standard_output(code, io_code): flushes the standard output; when a write to it failed (full disk,
//   /dev/full, closed), writes one line to the standard error and returns io_code if `code` was 0 (else
//   `code`, whose error was reported already).
#include <atomic>
#include <string>

namespace icobrdf {

void guard_standard_streams();
void install_stop_signals();
std::atomic<int>& record_stop_signals();
int finish_standard_output(int code, int io_code);

}  // namespace icobrdf
