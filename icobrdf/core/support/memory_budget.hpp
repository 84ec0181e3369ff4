#pragma once
// How much memory a request may use, and the refusal of one that needs more, before any work starts.
//
// available_memory() is the smallest of what the machine reports (Linux):
//   - MemAvailable of /proc/meminfo (memory the kernel can hand out without swapping),
//   - the cgroup limit minus the cgroup's current use (v2 memory.max / memory.current, or v1
//     memory.limit_in_bytes / memory.usage_in_bytes), the limit a container or a batch job sets,
//   - RLIMIT_AS minus the address space the process already maps (ulimit -v).
// set_memory_budget(bytes) replaces all of these (the program's --memory-budget, or the
// ICOBRDF_MEMORY_BUDGET environment variable).
//
// Estimates are of the peak resident bytes of the largest arrays a command allocates (pipeline/
// resource_estimate.hpp derives them per command and checks them against measured peak RSS); they are
// compared with the budget by require_memory.
#include <cstdint>
#include <string>

namespace icobrdf {

struct MemoryAvailable {
  double bytes = 0.0;
  std::string source;  // "MemAvailable", "cgroup limit", "RLIMIT_AS", "memory budget"
};

MemoryAvailable available_memory();

// bytes <= 0 restores measuring. Not thread-safe: set it before the work starts.
void set_memory_budget(double bytes);
// The measured figures (not a budget set above) are divided among `processes` processes of one job on
// this machine (the ranks of an mpirun on one node, icobrdf/cluster/distributed_run.hpp), each assumed to need as much.
// 1 (the default) restores the whole. Not thread-safe: set it before the work starts.
void set_memory_sharers(int processes);

// "8G", "8 GB", "512MiB", "1.5e9", "2T": decimal (kB, MB, GB, TB; K, M, G, T are read as KiB ... TiB
// like ulimit and cgroups do) or plain bytes. ArgumentError with the text quoted when it is not a
// positive finite size.
double parse_byte_size(const std::string& text);

// "13.5 GB", "850 MB", "12 kB": three significant digits, decimal units.
std::string byte_size_text(double bytes);

// Throws ResourceError when need_bytes exceeds available_memory():
//   "<what> needs about 40.2 GB of memory, 22.1 GB is available (MemAvailable); <advice>"
// `advice` names what would fit (for example "level 5 or lower fits"); empty for none.
void require_memory(double need_bytes, const std::string& what, const std::string& advice);
// The same against an availability already read (available_memory() reads /proc and /sys each call).
void require_memory(double need_bytes, const MemoryAvailable& have, const std::string& what, const std::string& advice);

}  // namespace icobrdf
