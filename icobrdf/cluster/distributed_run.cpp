#include "icobrdf/cluster/distributed_run.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstring>
#include <exception>
#include <iostream>

#include "icobrdf/cluster/cluster.hpp"
#include "icobrdf/cluster/distributed_projection.hpp"
#include "icobrdf/cluster/launcher.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"
#include "icobrdf/core/support/progress.hpp"

namespace icobrdf {
namespace {

// SIGTERM under mpirun: mpirun sends it to every rank when one fails or is killed. Rank 0 says so in one
// line (mpirun -q names the dead rank nowhere; without -q it does), every rank ends at once with the
// program's code for it: nothing has been written (rank 0 writes only after the projection's exchange, which
// a dead rank never joins). Set before the command starts; async-signal-safe (write, _exit).
char g_sigterm_line[256];
std::size_t g_sigterm_line_size = 0;
int g_sigterm_code = 1;
extern "C" void on_sigterm(int) {
  if (g_sigterm_line_size > 0) (void)!::write(STDERR_FILENO, g_sigterm_line, g_sigterm_line_size);
  ::_exit(g_sigterm_code);
}

void end_on_sigterm(int rank, int ranks, int code) {
  g_sigterm_code = code;
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

// The ranks of one run_distributed: the cluster, the projection's exchange, and whether set-up has ended.
struct RankState {
  Cluster& cluster;
  DistributedProjection& projection;
  const RankErrors& errors;
  bool agreed = false;

  // Prints `e` while `cluster` lives (its destructor waits for every rank, so every line is out before any
  // rank ends: mpirun stops the whole job when one rank exits non-zero) and ends the rank. Once printed, a
  // SIGTERM from mpirun ends rank 0 silently.
  [[noreturn]] void print_and_exit(std::exception_ptr e) const {
    errors.print(e);
    g_sigterm_line_size = 0;
    throw RankExit(errors.exit_code(e));
  }

  // This rank's own error `e`. In set-up, the ranks agree first, and only the lowest failed rank prints its
  // error; later, the error goes to the exchange when one is owed, and rank 0 prints it.
  [[noreturn]] void own_error(const std::exception& e, std::exception_ptr current) {
    const int rank = cluster.rank(), ranks = cluster.size();
    bool quiet = false;
    if (!agreed) {
      agreed = true;
      quiet = cluster.first_failed(false) < rank;
    } else if (projection.in_ring()) {
      // The other ranks wait for this one's block of P: no exchange can tell them, so the job ends here.
      std::cerr << "icobrdf: error: on rank " << rank << " of " << ranks << ": " << message_line(e.what())
                << " (while the blocks of P went round the ring; mpirun ends every rank)" << std::endl;
      cluster.abort(errors.exit_code(current));
    } else {
      quiet = projection.fail(e) && rank != 0;
    }
    if (quiet) throw RankExit(errors.exit_code(current));
    print_and_exit(error_on_rank(e, rank, ranks));
  }
};

void run_on_ranks(int projections, const std::function<void(const DistributedRun&)>& command, bool split_rows, const RankErrors& errors) {
  // The ranks on one machine share its memory.
  set_memory_sharers(launcher_local_size());
  const std::unique_ptr<Cluster> started = start_cluster();
  Cluster& cluster = *started;
  DistributedProjection projection(cluster, projections, split_rows);
  RankState state{cluster, projection, errors};
  DistributedRun run;
  run.rank = cluster.rank();
  run.ranks = cluster.size();
  run.share = projection.share();
  run.setup_done = [&state] {
    state.agreed = true;
    if (state.cluster.first_failed(true) >= 0) throw SetupFailed();  // the lowest failed rank says why
  };
  run.gather = [&cluster](double v) { return gather_on_rank0(cluster, v); };
  run.exchanges = [&projection] { return projection.projections_done(); };
  run.sample_sums = [&projection] { return projection.sample_sums(); };
  if (cluster.rank() != 0) set_progress_stream(nullptr);
  end_on_sigterm(cluster.rank(), cluster.size(), errors.sigterm_code);
  try {
    command(run);
  } catch (const SetupFailed&) {
    throw RankExit(errors.setup_failed_code);
  } catch (const RankExit&) {
    throw;
  } catch (const RankFailed& e) {  // from the exchange: rank 0 reports it
    if (cluster.rank() == 0) state.print_and_exit(e.error);
    throw RankExit(errors.exit_code(e.error));
  } catch (const std::exception& e) {
    state.own_error(e, std::current_exception());
  }
}

}  // namespace

std::unique_ptr<Cluster> start_cluster() {
  try {
    return std::make_unique<Cluster>();
  } catch (const std::exception&) {
    if (launcher_rank() > 0) throw RankExit(0);
    throw;
  }
}

void run_distributed(const std::string& /*what: messages name the rank instead*/, int projections,
                     const std::function<void(const DistributedRun&)>& command, bool split_rows, const RankErrors& errors) {
  if (!started_by_mpirun()) return command(DistributedRun{});
  run_on_ranks(projections, command, split_rows, errors);
}

}  // namespace icobrdf
