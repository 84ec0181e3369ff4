#include "icobrdf/core/support/memory_budget.hpp"

#include <sys/resource.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "icobrdf/core/support/error.hpp"

namespace icobrdf {
namespace {

double& budget_slot() {
  static double budget = 0.0;
  return budget;
}

// A number from the first line of a file; nullopt-like negative when absent or "max".
double first_number(const std::string& path) {
  std::ifstream in(path);
  std::string word;
  if (!(in >> word) || word == "max") return -1.0;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  return end != word.c_str() && *end == '\0' && v >= 0 ? v : -1.0;
}

// "Key:   123 kB" from a /proc file, in bytes; negative when absent.
double proc_field_bytes(const std::string& path, const std::string& key) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    if (line.compare(0, key.size() + 1, key + ":") != 0) continue;
    std::istringstream fields(line.substr(key.size() + 1));
    double v = 0;
    std::string unit;
    if (!(fields >> v)) return -1.0;
    fields >> unit;
    return unit == "kB" ? v * 1024.0 : v;
  }
  return -1.0;
}

// The cgroup this process belongs to (v2 unified hierarchy "0::/path"), or "" for the root.
std::string cgroup_v2_path() {
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line))
    if (line.compare(0, 3, "0::") == 0) return line.substr(3);
  return "";
}

void consider(MemoryAvailable& best, double bytes, const char* source) {
  if (bytes < 0) return;
  if (best.source.empty() || bytes < best.bytes) best = {bytes, source};
}

}  // namespace

void set_memory_budget(double bytes) { budget_slot() = bytes > 0 ? bytes : 0.0; }

namespace {
int& sharers_slot() {
  static int sharers = 1;
  return sharers;
}
}  // namespace

void set_memory_sharers(int processes) { sharers_slot() = processes > 1 ? processes : 1; }

MemoryAvailable available_memory() {
  if (budget_slot() > 0) return {budget_slot(), "memory budget"};
  MemoryAvailable best;
  consider(best, proc_field_bytes("/proc/meminfo", "MemAvailable"), "MemAvailable");
  // cgroup v2: the process's own group first, then the mount point's root file (containers mount their group there).
  for (const std::string& dir : {"/sys/fs/cgroup" + cgroup_v2_path(), std::string("/sys/fs/cgroup")}) {
    const double limit = first_number(dir + "/memory.max"), used = first_number(dir + "/memory.current");
    if (limit >= 0) {
      consider(best, std::max(0.0, limit - std::max(used, 0.0)), "cgroup limit");
      break;
    }
  }
  {  // cgroup v1; an unlimited group reports a huge number, which never wins the minimum
    const double limit = first_number("/sys/fs/cgroup/memory/memory.limit_in_bytes");
    const double used = first_number("/sys/fs/cgroup/memory/memory.usage_in_bytes");
    if (limit >= 0 && limit < 1e18) consider(best, std::max(0.0, limit - std::max(used, 0.0)), "cgroup limit");
  }
  rlimit rl{};
  if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY) {
    const double mapped = proc_field_bytes("/proc/self/status", "VmSize");
    consider(best, std::max(0.0, static_cast<double>(rl.rlim_cur) - std::max(mapped, 0.0)), "RLIMIT_AS");
  }
  if (best.source.empty()) best = {std::numeric_limits<double>::infinity(), "no limit found"};
  // The machine-wide figures are shared by the processes of one job on this machine (RLIMIT_AS is per
  // process, but dividing it too only errs on the safe side).
  if (sharers_slot() > 1) {
    best.bytes /= sharers_slot();
    best.source += " / " + std::to_string(sharers_slot()) + " ranks on this node";
  }
  return best;
}

double parse_byte_size(const std::string& text) {
  const auto bad = [&] {
    return ArgumentError("memory budget: expected a size such as 8G, 512MB or 2e9 bytes, found '" + quoted_text(text) + "'");
  };
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin) throw bad();
  std::string unit(end);
  unit.erase(0, unit.find_first_not_of(' '));
  for (auto& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  double scale = 0.0;
  if (unit.empty() || unit == "B") scale = 1;
  else if (unit == "KB") scale = 1e3;
  else if (unit == "MB") scale = 1e6;
  else if (unit == "GB") scale = 1e9;
  else if (unit == "TB") scale = 1e12;
  else if (unit == "K" || unit == "KIB") scale = 1024.0;
  else if (unit == "M" || unit == "MIB") scale = 1024.0 * 1024;
  else if (unit == "G" || unit == "GIB") scale = 1024.0 * 1024 * 1024;
  else if (unit == "T" || unit == "TIB") scale = 1024.0 * 1024 * 1024 * 1024;
  else throw bad();
  const double bytes = v * scale;
  if (!std::isfinite(bytes) || bytes < 1) throw bad();
  return bytes;
}

std::string byte_size_text(double bytes) {
  static const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB"};
  int u = 0;
  while (bytes >= 999.5 && u < 5) {
    bytes /= 1000;
    ++u;
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, bytes < 9.995 && u > 0 ? "%.2f %s" : bytes < 99.95 && u > 0 ? "%.1f %s" : "%.0f %s", bytes, units[u]);
  return buf;
}

void require_memory(double need_bytes, const std::string& what, const std::string& advice) {
  require_memory(need_bytes, available_memory(), what, advice);
}

void require_memory(double need_bytes, const MemoryAvailable& have, const std::string& what, const std::string& advice) {
  if (need_bytes <= have.bytes) return;
  throw ResourceError(what + " needs about " + byte_size_text(need_bytes) + " of memory, " + byte_size_text(have.bytes) +
                      " is available (" + have.source + ")" + (advice.empty() ? "" : "; " + advice));
}

}  // namespace icobrdf
