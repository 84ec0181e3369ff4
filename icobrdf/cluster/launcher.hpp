#pragma once
// Whether this process was started by an MPI launcher (mpirun, srun), read from the launcher's environment
// only: header-only and without MPI, so that a program built without MPI can refuse to run under mpirun
// (every rank would do the whole work) and one built with it calls MPI_Init only then
// (icobrdf/cluster/cluster.hpp).
#include <cstdlib>

namespace icobrdf {

// The number of processes the launcher started: OMPI_COMM_WORLD_SIZE (OpenMPI's mpirun) or PMI_SIZE (PMI-2
// launchers such as srun --mpi=pmi2); 1 when only PMIX_RANK says a PMIx launcher (srun --mpi=pmix) started
// the process (its size is not in the environment); 0 when no launcher did.
inline int launcher_world_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* v = std::getenv(name)) {
      const int n = std::atoi(v);
      if (n > 0) return n;
    }
  return std::getenv("PMIX_RANK") ? 1 : 0;
}

inline bool started_by_mpirun() { return launcher_world_size() > 0; }

// This process's rank as the launcher numbered it: OMPI_COMM_WORLD_RANK (OpenMPI), PMI_RANK (PMI-2) or
// PMIX_RANK (PMIx); -1 when no launcher says. Known before MPI_Init, so that output every rank would print
// alike (a usage error: every rank parses the same command line) can come from rank 0 alone.
inline int launcher_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"})
    if (const char* v = std::getenv(name)) {
      char* end = nullptr;
      const long r = std::strtol(v, &end, 10);
      if (end != v && *end == '\0' && r >= 0) return static_cast<int>(r);
    }
  return -1;
}

// The processes the launcher started on this machine: OMPI_COMM_WORLD_LOCAL_SIZE (OpenMPI), or
// 1 when OpenMPI does not say (srun: pass --memory-budget, since SLURM_TASKS_PER_NODE can list several nodes).
inline int launcher_local_size() {
  if (const char* v = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE")) {
    const int n = std::atoi(v);
    if (n > 0) return n;
  }
  return 1;
}

}  // namespace icobrdf
