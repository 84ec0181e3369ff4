#include "cli/error_report.hpp"

#include <CLI/CLI.hpp>

#include <iostream>
#include <new>
#include <stdexcept>

#include "cli/exit_codes.hpp"
#include "icobrdf/core/support/error.hpp"
#include "icobrdf/io/utf8_text.hpp"

namespace icobrdf::cli {

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
  } catch (const ResourceError& x) {
    return error(x, kExitResources, "error", "; --memory-budget overrides the limit");
  } catch (const std::bad_alloc&) {
    return ErrorReport{kOutOfMemoryLine, kExitResources};
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
