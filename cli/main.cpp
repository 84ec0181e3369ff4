// icobrdf: command-line entry point. Subcommands register in cli/commands.hpp.
#include <exception>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/exit_codes.hpp"
#include "core/error.hpp"

int main(int argc, char** argv) {
  using namespace icobrdf::cli;
  CLI::App app{"icobrdf: BRDFs as exact linear algebra on an equal-area icosahedral hemisphere tessellation"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("icobrdf ") + ICOBRDF_VERSION);
  for (auto& [name, adder] : command_registry()) adder(app);
  app.failure_message([](const CLI::App*, const CLI::Error& e) { return icobrdf::message_line(e.what()) + "\n"; });
  const auto fail = [](const std::exception& e, int code, const char* kind = "error") {
    std::cerr << "icobrdf: " << kind << ": " << icobrdf::message_line(e.what()) << "\n";  // one short line
    return code;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::RuntimeError& e) {
    return e.get_exit_code();  // a command's own exit code (e.g. 130 after SIGINT), message already printed
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  } catch (const icobrdf::ArgumentError& e) {
    return fail(e, kExitUsage);
  } catch (const icobrdf::InputError& e) {
    return fail(e, kExitInput);
  } catch (const icobrdf::UnsupportedError& e) {
    return fail(e, kExitUnsupported);
  } catch (const icobrdf::IoError& e) {
    return fail(e, kExitIo);
  } catch (const std::exception& e) {
    return fail(e, kExitInternal, "internal error");
  }
  return kExitOk;
}
