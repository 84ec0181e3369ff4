#pragma once
// What this process has used so far, from getrusage(RUSAGE_SELF): its peak resident memory and its CPU time.
// Per process: under mpirun each rank reports its own (gathered by icobrdf/cluster/distributed_run.hpp).

namespace icobrdf::lab {

// Peak resident memory of this process so far, in bytes (ru_maxrss, kilobytes on Linux).
double peak_resident_bytes();

// CPU seconds of this process so far, all threads, user + system (microsecond resolution).
double process_cpu_seconds();

}  // namespace icobrdf::lab
