#include "cli/error_report.hpp"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>
#include <stdexcept>

#include "cli/exit_codes.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/utf8_text.hpp"

namespace icobrdf::cli {
namespace {

// The advice per subcommand: what grows its memory. Commands not named read files or print tables.
constexpr const char* kOutOfMemoryAdvice[][2] = {
    {"lut", "a lower level or order needs less"},
    {"fit", "a lower level or order, or fewer samples, needs less"},
    {"bank", "a lower level or order, or fewer materials per process, needs less"},
    {"bench", "a lower level or order needs less"},
    {"sample", "a lower --level needs less (the number of draws does not change it)"},
    {"plot", "a smaller picture or a lower level needs less"},
    {"eval", "fewer directions (--at) or a smaller SOURCE need less"},
};
constexpr char kDefaultAdvice[] = "a smaller input needs less";
char g_out_of_memory_line[256] = "icobrdf: error: out of memory: an allocation failed; a smaller input needs less\n";

}  // namespace

const char* out_of_memory_line() { return g_out_of_memory_line; }

void set_out_of_memory_command(const char* command) {
  const char* advice = kDefaultAdvice;
  for (const auto& entry : kOutOfMemoryAdvice)
    if (std::strcmp(entry[0], command) == 0) advice = entry[1];
  std::snprintf(g_out_of_memory_line, sizeof g_out_of_memory_line, "icobrdf: error: out of memory: an allocation failed in %s; %s\n",
                command, advice);
}

ErrorReport report_of(std::exception_ptr e) {
  const auto error = [](const std::exception& x, int code, const char* kind = "error", const std::string& more = "") {
    return ErrorReport{std::string("icobrdf: ") + kind + ": " + valid_utf8_text(message_line(x.what())) + more + "\n", code};
  };
  try {
    std::rethrow_exception(e);
  } catch (const CLI::RuntimeError& x) {
    return ErrorReport{"", x.get_exit_code()};
  } catch (const RankExit& x) {
    return ErrorReport{"", x.code};
  } catch (const ArgumentError& x) {
    return error(x, kExitUsage);
  } catch (const InputError& x) {
    return error(x, kExitInput);
  } catch (const UnsupportedError& x) {
    return error(x, kExitUnsupported);
  } catch (const IoError& x) {
    return error(x, kExitIo);
  } catch (const ResourceError& x) {  // a memory limit can be set by hand, free disk space cannot
    const bool memory = std::strstr(x.what(), " of memory") != nullptr;
    return error(x, kExitResources, "error", memory ? "; --memory-budget overrides the limit" : "");
  } catch (const std::bad_alloc&) {
    return ErrorReport{out_of_memory_line(), kExitResources};
  } catch (const std::exception& x) {
    return error(x, kExitInternal, "internal error");
  } catch (...) {
    return ErrorReport{"icobrdf: internal error: the program stopped without an error message\n", kExitInternal};
  }
}

void print_now(std::exception_ptr e) {
  const ErrorReport r = report_of(e);
  std::cerr << r.line << std::flush;
  throw CLI::RuntimeError(r.code);
}

RankErrors rank_errors() {
  RankErrors errors;
  errors.exit_code = [](std::exception_ptr e) { return report_of(e).code; };
  errors.print = [](std::exception_ptr e) { std::cerr << report_of(e).line << std::flush; };
  errors.setup_failed_code = kExitUnsupported;
  errors.sigterm_code = kExitTerminated;
  return errors;
}

}  // namespace icobrdf::cli
