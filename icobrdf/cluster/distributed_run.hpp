#pragma once
// A command whose streaming projection runs on every rank of an mpirun job (`icobrdf fit`, `bench
// streaming`; icobrdf/cluster/distributed_projection.hpp). Without mpirun, or in a build without MPI,
// run_distributed calls the command once with a one-process DistributedRun; a build without MPI refuses an
// mpirun of several processes (every process would do the whole work). This header is usable without MPI
// (as icobrdf/cluster/launcher.hpp is): the MPI side is compiled into icobrdf_cluster only.
//
// Under mpirun:
//   - set-up (reading the source, checking the output path on rank 0) ends with setup_done(), where the
//     ranks agree: if a rank failed, rank 0 says which and every rank stops (the failed rank prints its own
//     error, as only it knows it);
//   - a failure after that goes to the projection's exchange (DistributedProjection::fail), so rank 0 prints
//     one line naming the rank and the other ranks end with the same exit code and no message;
//   - progress lines come from rank 0 only;
//   - the memory a rank may use is what the machine has divided by the ranks on it (memory_budget.hpp
//     set_memory_sharers), since the ranks of a node share it.
// The program says how an error is printed and which exit code it gets (RankErrors); a rank that ends
// after its error was printed (by itself or by rank 0) throws RankExit with that code.
#include <fmt/core.h>

#include <exception>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "icobrdf/cluster/launcher.hpp"
#include "icobrdf/core/projection/streaming_projection.hpp"
#include "icobrdf/core/support/error.hpp"

namespace icobrdf {

#ifdef ICOBRDF_WITH_MPI
class Cluster;
#endif

struct DistributedRun {
  int rank = 0, ranks = 1;
  std::shared_ptr<const StreamingShare> share;  // null in one process
  std::function<void()> setup_done = [] {};
  // Rank 0 gets one value per rank (rank order); one process gets its own value.
  std::function<std::vector<double>(double)> gather = [](double v) { return std::vector<double>{v}; };
  // Projections whose result was exchanged so far (0 in one process).
  std::function<int()> exchanges = [] { return 0; };
  // Sums of a fit of scattered samples split over the ranks so far (0 in one process).
  std::function<int()> sample_sums = [] { return 0; };
  bool writes() const { return rank == 0; }
};

// This rank ends with exit code `code`; the error's line, if any, was printed already.
struct RankExit : std::exception {
  explicit RankExit(int c) : code(c) {}
  const char* what() const noexcept override { return "the rank ends; its error was printed"; }
  int code;
};

// How the program reports errors on a rank.
struct RankErrors {
  std::function<int(std::exception_ptr)> exit_code;  // the exit code the program gives the error
  std::function<void(std::exception_ptr)> print;     // prints the error's one line now (and returns)
  int setup_failed_code = 1;  // exit code of a rank whose set-up succeeded while another rank's failed
  int sigterm_code = 1;       // exit code after mpirun's SIGTERM
};

#ifdef ICOBRDF_WITH_MPI
// Runs `command` as described above; `what` names the command in messages ("fit"), `projections` is how
// many projections every rank makes (DistributedProjection).
// `split_rows`: the ranks split the projection operators by rows (icobrdf/core/projection/row_split_projection.hpp:
// memory per rank O(cells x modes / ranks)); a rank that fails while the blocks go round the ring prints its
// error and ends the job (mpirun's own lines follow).
void run_distributed(const std::string& what, int projections, const std::function<void(const DistributedRun&)>& command,
                     bool split_rows, const RankErrors& errors);

// Starts MPI (icobrdf/cluster/cluster.hpp) on a rank of an mpirun job. An error raised before MPI starts (a bad
// ICOBRDF_MPI_PIECE_BYTES) is the same on every rank: rank 0 rethrows it (the program prints its one line), the
// others end quietly with RankExit(0), as for a usage error (a non-zero exit would make mpirun stop rank 0
// before its line is out; mpirun returns rank 0's code).
std::unique_ptr<Cluster> start_cluster();
#else
inline void run_distributed(const std::string& what, int /*projections*/, const std::function<void(const DistributedRun&)>& command,
                            bool /*split_rows*/, const RankErrors& /*errors*/) {
  if (launcher_world_size() > 1)
    throw UnsupportedError(fmt::format("{}: started by mpirun with {} processes, but this icobrdf was built without MPI (every process would "
                                       "do the whole work); install libopenmpi-dev and rebuild, or run it without mpirun",
                                       what, launcher_world_size()));
  command(DistributedRun{});
}
#endif

}  // namespace icobrdf
