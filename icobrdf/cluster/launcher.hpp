#pragma once
// Whether this process was started by an MPI launcher (mpirun, srun), read from the launcher's environment
// only: header-only and without MPI, so that a program built without MPI can refuse to run under mpirun
// (every rank would do the whole work) and one built with it calls MPI_Init only then
// (icobrdf/cluster/cluster.hpp).
#include <cstdlib>

namespace icobrdf {

// The number of processes the launcher started: OMPI_COMM_WORLD_SIZE (OpenMPI's mpirun), else PMIX_SIZE or
// PMI_SIZE (other launchers); 0 when the program was not started by one.
inline int launcher_world_size() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_SIZE", "PMI_SIZE"})
    if (const char* v = std::getenv(name)) {
      const int n = std::atoi(v);
      if (n > 0) return n;
    }
  return 0;
}

inline bool started_by_mpirun() { return launcher_world_size() > 0; }

}  // namespace icobrdf
