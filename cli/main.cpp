// icobrdf: command-line entry point. Subcommands register in cli/commands.hpp.
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>

#include "cli/commands.hpp"
#include "cli/error_report.hpp"
#include "cli/exit_codes.hpp"
#include "icobrdf/blas/blas_dense_kernels.hpp"
#include "icobrdf/cluster/launcher.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/core/support/progress.hpp"
#include "icobrdf/io/atomic_write.hpp"
#include "icobrdf/io/program_end.hpp"

namespace {

// Large temporaries come and go by the hundred in fits (Eigen's product packing buffers of several MB, the
// unknowns^2 matrices of sample fits, 39 MB at order 10): glibc serves each beyond its mmap threshold from a
// fresh mapping and unmaps it on free, so every first write faults page by page (700,000 faults and 1.6 s of
// system time in the 20,000-sample order-10 fit, 135,000 and 0.5 s with these settings). Blocks up to
// kHeapBlockBytes stay in the heap, and up to kKeptTopBytes of freed heap top stay mapped for the next one.
constexpr int kHeapBlockBytes = 64 << 20;
constexpr int kKeptTopBytes = 128 << 20;

void tune_allocator() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, kHeapBlockBytes);
  mallopt(M_TRIM_THRESHOLD, kKeptTopBytes);
#endif
}

// An exception that leaves a worker thread (an OpenMP region cannot pass it on) ends the program through
// std::terminate. Say what it was in one line, remove the temporaries of unfinished atomic writes (so no
// partial output is left) and exit with the code of its kind, instead of the default abort (exit 134).
[[noreturn]] void on_terminate() {
  using namespace icobrdf::cli;
  // Nothing here may allocate before the kind is known: memory may be exhausted.
  static const char kUnknown[] = "icobrdf: internal error: the program stopped without an error message\n";
  int code = kExitInternal;
  const char* fixed = kUnknown;
  std::string line;
  if (const auto e = std::current_exception()) {
    try {
      std::rethrow_exception(e);
    } catch (const std::bad_alloc&) {
      code = kExitResources;
      fixed = out_of_memory_line();
    } catch (const std::exception& x) {
      try {
        line = "icobrdf: internal error: " + icobrdf::message_line(x.what()) + "\n";
      } catch (...) {
      }
    } catch (...) {
    }
  }
  icobrdf::remove_unfinished_temporaries();
  const char* text = line.empty() ? fixed : line.c_str();
  (void)!::write(STDERR_FILENO, text, std::strlen(text));
  std::_Exit(code);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace icobrdf::cli;
  tune_allocator();
  icobrdf::guard_standard_streams();  // before any file is opened (icobrdf/io/program_end.hpp)
  icobrdf::install_stop_signals();
  icobrdf::set_default_dense_kernels(&icobrdf::fit_dense_kernels());  // the sample fits' kernels (OpenBLAS's when as wide as Eigen's)
  CLI::App app{"icobrdf: BRDFs as exact linear algebra on an equal-area icosahedral hemisphere tessellation"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("icobrdf ") + ICOBRDF_VERSION);
  std::set_terminate(on_terminate);
  // Options of every command (before or after its name): the memory limit its up-front estimates are
  // checked against, and the progress lines of long work.
  app.fallthrough();
  app.add_option_function<std::string>(
         "--memory-budget", [](const std::string& v) { icobrdf::set_memory_budget(icobrdf::parse_byte_size(v)); },
         "Memory the work may use (e.g. 8G, 512MB), instead of what the machine reports as available")
      ->envname("ICOBRDF_MEMORY_BUDGET");
  bool quiet = false;
  app.add_flag("--no-progress", quiet, "No progress lines on stderr for long work");
  app.parse_complete_callback([&quiet] { icobrdf::set_progress_stream(quiet ? nullptr : &std::cerr); });
  // ICOBRDF_PROGRESS_DELAY: seconds before the first progress line (0: at once), for scripts and tests.
  if (const char* d = std::getenv("ICOBRDF_PROGRESS_DELAY")) icobrdf::set_progress_delay(std::atof(d));
  for (auto& [name, adder] : command_registry()) adder(app);
  for (CLI::App* sub : app.get_subcommands({})) sub->preparse_callback([sub](std::size_t) { set_out_of_memory_command(sub->get_name().c_str()); });
  app.failure_message([](const CLI::App*, const CLI::Error& e) { return icobrdf::message_line(e.what()) + "\n"; });
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    return icobrdf::finish_standard_output(e.get_exit_code(), kExitIo);  // a command's own exit code (e.g. 130 after SIGINT), message already printed
  } catch (const CLI::ParseError& e) {
    // Under mpirun every rank parses the same command line and would print the same usage error (or the help):
    // rank 0 prints it and exits with the code; the others exit quietly with 0, since a non-zero exit makes
    // mpirun stop rank 0, possibly before its line is out (mpirun still returns rank 0's code).
    if (icobrdf::launcher_rank() > 0) return kExitOk;
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  } catch (const std::bad_alloc&) {
    // Exit at once: after an allocation failed, libraries' exit handlers (OpenBLAS joining its threads) can hang.
    std::cout.flush();
    (void)!::write(STDERR_FILENO, out_of_memory_line(), std::strlen(out_of_memory_line()));
    std::_Exit(kExitResources);
  } catch (...) {
    const ErrorReport r = report_of(std::current_exception());  // one short line (cli/error_report.hpp)
    std::cerr << r.line;
    return r.code;
  }
  return icobrdf::finish_standard_output(kExitOk, kExitIo);
}
