#pragma once
// Provenance of a run, as reports record it: the command line as typed and the time it started.
#include <string>

namespace icobrdf::lab {

// This process's command line from /proc/self/cmdline: the program by its file name, arguments separated
// by spaces, an argument quoted with '...' when empty or when it holds a space, tab or quote.
std::string command_line();

// The current time in UTC, ISO 8601 to the second: "2026-05-22T10:04:05Z".
std::string now_iso8601();

}  // namespace icobrdf::lab
