#pragma once
// Free disk space of a folder's file system, and the refusal of a request that needs more, before any work
// starts (as icobrdf/core/support/memory_budget.hpp refuses memory).
//
// The free space is statvfs's f_bavail x f_frsize: the bytes an unprivileged process may still write
// there (the blocks reserved for root excluded). It is a snapshot: other writers may take space meanwhile,
// so a write can still fail later (and is reported then); the check catches a request far too large at once.
#include <string>

namespace icobrdf {

// Bytes free to this process in the file system holding `folder`; negative when statvfs fails (no such
// folder, no permission).
double free_disk_bytes(const std::string& folder);

// Throws ResourceError when need_bytes exceed free_disk_bytes(folder):
//   "<what> needs about 2.40 TB of disk space in /tmp, 1.10 GB is free there (statvfs); <advice>"
// `advice` names what would fit (for example "set TMPDIR to a folder with more space"); empty for none.
// Does nothing when the folder cannot be queried: the write that follows reports that folder's error.
void require_disk_space(double need_bytes, const std::string& folder, const std::string& what, const std::string& advice);

}  // namespace icobrdf
