#pragma once
// The one line and exit code the program gives an error (cli/exit_codes.hpp), shared by main() and by the
// ranks of an mpirun job, which must print before they finish MPI: mpirun ends the whole job as soon as one
// rank exits with a non-zero code, so a rank that printed after MPI_Finalize could be stopped first and its
// line lost (icobrdf/cluster/cluster.hpp: the Cluster's destructor waits for every rank).
#include <exception>
#include <string>

#include "icobrdf/cluster/distributed_run.hpp"

namespace icobrdf::cli {

// The line of an allocation failure, naming what to reduce in the command that ran ("a lower level or order
// needs less" for lut, fit, bank; "a lower --level" for sample; a smaller input for the readers); main() and
// the terminate handler write it without allocating (cli/main.cpp).
const char* out_of_memory_line();
// Chooses out_of_memory_line()'s advice for the subcommand `command` (set when the parser meets it).
void set_out_of_memory_command(const char* command);

struct ErrorReport {
  std::string line;  // "icobrdf: error: ...\n" (or "icobrdf: internal error: ...\n"), one line
  int code = 0;      // the exit code of the error's kind
};

// ArgumentError 2, InputError 3, UnsupportedError 4, IoError 5, ResourceError and bad_alloc 6 (a
// ResourceError's line says that --memory-budget overrides the limit), CLI::RuntimeError and RankExit (a rank
// of an mpirun job, icobrdf/cluster/distributed_run.hpp) their own code and no line (the message was printed
// already), anything else 70 as an internal error.
ErrorReport report_of(std::exception_ptr e);

// Prints report_of(e)'s line now and throws CLI::RuntimeError with its code (main() then exits with it
// without printing again).
[[noreturn]] void print_now(std::exception_ptr e);

// The program's reporting for the ranks of an mpirun job (icobrdf/cluster/distributed_run.hpp): report_of's
// line and code, 4 for a rank whose set-up succeeded while another's failed, 143 after mpirun's SIGTERM.
RankErrors rank_errors();

}  // namespace icobrdf::cli
