#include "cli/distributed_run.hpp"

#include <fmt/core.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>

#include "cli/commands.hpp"
#include "cli/error_report.hpp"
#include "cli/exit_codes.hpp"
#include "icobrdf/cluster/launcher.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/core/support/progress.hpp"
#ifdef ICOBRDF_WITH_MPI
#include "icobrdf/cluster/distributed_projection.hpp"
#endif

namespace icobrdf::cli {
namespace {

#ifdef ICOBRDF_WITH_MPI
// The exit code main() gives the error `e` (cli/error_report.hpp), for ranks that end without printing it.
int exit_code_of(std::exception_ptr e) { return report_of(e).code; }

// SIGTERM under mpirun: mpirun sends it to every rank when one fails or is killed. Rank 0 says so in one
// line (mpirun -q names the dead rank nowhere; without -q it does), every rank ends at once with 128 + 15:
// nothing has been written (rank 0 writes only after the projection's exchange, which a dead rank never
// joins). Set before MPI starts; async-signal-safe (write, _exit).
char g_sigterm_line[256];
std::size_t g_sigterm_line_size = 0;
extern "C" void on_sigterm(int) {
  if (g_sigterm_line_size > 0) (void)!::write(STDERR_FILENO, g_sigterm_line, g_sigterm_line_size);
  ::_exit(kExitTerminated);
}

void end_on_sigterm(int rank, int ranks) {
  if (rank == 0) {
    const std::string line = fmt::format("icobrdf: error: stopped by SIGTERM on rank 0 of {}: mpirun ends every rank when one fails or is "
                                         "killed (without -q it names the rank); nothing was written\n",
                                         ranks);
    g_sigterm_line_size = std::min(line.size(), sizeof g_sigterm_line);
    std::memcpy(g_sigterm_line, line.data(), g_sigterm_line_size);
  }
  struct sigaction sa {};
  sa.sa_handler = on_sigterm;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGTERM, &sa, nullptr);
}

// Set-up failed on another rank (this rank's own set-up succeeded); that rank prints why.
struct SetupFailed : std::exception {};
#endif

}  // namespace

#ifdef ICOBRDF_WITH_MPI
std::unique_ptr<Cluster> start_cluster() {
  try {
    return std::make_unique<Cluster>();
  } catch (const std::exception&) {
    if (launcher_rank() > 0) throw CLI::RuntimeError(kExitOk);
    throw;
  }
}
#endif

double peak_resident_bytes() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return 1024.0 * static_cast<double>(u.ru_maxrss);  // kilobytes on Linux
}

void run_distributed(const std::string& what, int projections, const std::function<void(const DistributedRun&)>& command,
                     bool split_rows) {
#ifdef ICOBRDF_WITH_MPI
  (void)what;  // messages name the rank instead
  if (!started_by_mpirun()) return command(DistributedRun{});
  // The ranks on one machine share its memory.
  set_memory_sharers(launcher_local_size());
  const std::unique_ptr<Cluster> started = start_cluster();
  Cluster& cluster = *started;
  DistributedProjection projection(cluster, projections, split_rows);
  DistributedRun run;
  run.rank = cluster.rank();
  run.ranks = cluster.size();
  run.share = projection.share();
  bool agreed = false;
  run.setup_done = [&] {
    agreed = true;
    if (cluster.first_failed(true) >= 0) throw SetupFailed();  // the lowest failed rank says why
  };
  run.gather = [&cluster](double v) { return gather_on_rank0(cluster, v); };
  run.exchanges = [&projection] { return projection.projections_done(); };
  run.sample_sums = [&projection] { return projection.sample_sums(); };
  if (cluster.rank() != 0) set_progress_stream(nullptr);
  end_on_sigterm(cluster.rank(), cluster.size());
  const int rank = cluster.rank(), ranks = cluster.size();
  // A rank prints its error here, while `cluster` lives: its destructor waits for every rank, so every line
  // is out before any rank ends (mpirun stops the whole job when one rank exits non-zero). Once printed,
  // a SIGTERM from mpirun ends rank 0 silently.
  const auto print = [](std::exception_ptr e) {
    try {
      print_now(e);
    } catch (...) {
      g_sigterm_line_size = 0;
      throw;
    }
  };
  try {
    command(run);
  } catch (const SetupFailed&) {
    throw CLI::RuntimeError(kExitUnsupported);
  } catch (const RankFailed& e) {  // from the exchange: rank 0 reports it
    if (rank == 0) print(e.error);
    throw CLI::RuntimeError(exit_code_of(e.error));
  } catch (const std::exception& e) {
    // This rank's own error. In set-up, the ranks agree first, and only the lowest failed rank prints its
    // error; later, the error goes to the exchange when one is owed, and rank 0 prints it.
    bool quiet = false;
    if (!agreed) {
      agreed = true;
      quiet = cluster.first_failed(false) < rank;
    } else if (projection.in_ring()) {
      // The other ranks wait for this one's block of P: no exchange can tell them, so the job ends here.
      std::cerr << "icobrdf: error: on rank " << rank << " of " << ranks << ": " << message_line(e.what())
                << " (while the blocks of P went round the ring; mpirun ends every rank)" << std::endl;
      cluster.abort(exit_code_of(std::current_exception()));
    } else {
      quiet = projection.fail(e) && rank != 0;
    }
    if (quiet) throw CLI::RuntimeError(exit_code_of(std::current_exception()));
    print(error_on_rank(e, rank, ranks));
  }
#else
  (void)projections;
  (void)split_rows;
  if (launcher_world_size() > 1)
    throw UnsupportedError(fmt::format("{}: started by mpirun with {} processes, but this icobrdf was built without MPI (every process would "
                                       "do the whole work); install libopenmpi-dev and rebuild, or run it without mpirun",
                                       what, launcher_world_size()));
  command(DistributedRun{});
#endif
}

}  // namespace icobrdf::cli
