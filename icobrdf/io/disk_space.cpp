#include "icobrdf/io/disk_space.hpp"

#include <sys/statvfs.h>

#include "icobrdf/core/support/error.hpp"
#include "icobrdf/core/support/memory_budget.hpp"

namespace icobrdf {

double free_disk_bytes(const std::string& folder) {
  struct statvfs fs {};
  if (::statvfs(folder.c_str(), &fs) != 0) return -1.0;
  return static_cast<double>(fs.f_bavail) * static_cast<double>(fs.f_frsize);
}

void require_disk_space(double need_bytes, const std::string& folder, const std::string& what, const std::string& advice) {
  const double free_bytes = free_disk_bytes(folder);
  if (free_bytes < 0 || need_bytes <= free_bytes) return;
  throw ResourceError(what + " needs about " + byte_size_text(need_bytes) + " of disk space in " + folder + ", " +
                      byte_size_text(free_bytes) + " is free there (statvfs)" + (advice.empty() ? "" : "; " + advice));
}

}  // namespace icobrdf
