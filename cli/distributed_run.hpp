#pragma once
// Commands whose streaming projection runs on every rank of an mpirun job (`fit`, `bench streaming`;
// icobrdf/cluster/distributed_projection.hpp). Without mpirun, or in a build without MPI, `run` calls the
// command once with a one-process DistributedRun; a build without MPI refuses an mpirun of several processes
// (every process would do the whole work).
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
#include <functional>
#include <memory>
#include <string>

#include "icobrdf/core/projection/streaming_projection.hpp"

#ifdef ICOBRDF_WITH_MPI
namespace icobrdf {
class Cluster;
}
#endif

namespace icobrdf::cli {

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

// Runs `command` as described above; `what` names the command in messages ("fit"), `projections` is how
// many projections every rank makes (DistributedProjection).
// `split_rows`: the ranks split the projection operators by rows (icobrdf/core/projection/row_split_projection.hpp: memory
// per rank O(cells x modes / ranks)); a rank that fails while the blocks go round the ring prints its error
// and ends the job (mpirun's own lines follow).
void run_distributed(const std::string& what, int projections, const std::function<void(const DistributedRun&)>& command,
                     bool split_rows = false);

#ifdef ICOBRDF_WITH_MPI
// Starts MPI (icobrdf/cluster/cluster.hpp) on a rank of an mpirun job. An error raised before MPI starts (a bad
// ICOBRDF_MPI_PIECE_BYTES) is the same on every rank: rank 0 rethrows it (main prints its one line), the others
// end quietly with exit code 0, as for a usage error (cli/main.cpp: a non-zero exit would make mpirun stop
// rank 0 before its line is out; mpirun returns rank 0's code).
std::unique_ptr<Cluster> start_cluster();
#endif

// Peak resident memory of this process so far, in bytes (getrusage).
double peak_resident_bytes();

}  // namespace icobrdf::cli
