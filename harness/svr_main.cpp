// svr: the spectral volume renderer's command line. Every subcommand is defined in its own
// *_command.cpp and listed in commands.cpp; main only dispatches and maps errors to exit codes.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <exception>

#include "harness/build_info.h"
#include "harness/command.h"
#include "harness/interrupt.h"
#include "base/data_dir.h"
#include "base/error.h"

int main(int argc, char** argv) {
  CLI::App app{"svr — spectral volume rendering with post-illumination (Bergner et al. 2002)"};
  app.require_subcommand(1);
  svr::CommandContext context{svr::defaultDataDir()};
  app.add_option("--data", context.data_dir, "data directory (spectra/, volumes/, scenes/)")
      ->capture_default_str();
  app.set_version_flag("--version", [&] { return svr::buildDescription(context.data_dir); },
                       "the version and what this build holds");
  for (const auto& command : svr::commandEntries())
    command.define(*app.add_subcommand(command.name, command.help), context);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const svr::Error& e) {
    fmt::print(stderr, "svr: error: {}\n", e.what());
    return 2;
  } catch (const svr::Interrupted&) {
    fmt::print(stderr, "svr: interrupted\n");
    return svr::kInterruptedExitCode;
  } catch (const std::exception& e) {
    fmt::print(stderr, "svr: internal error: {}\n", e.what());
    return 3;
  }
  return context.status;
}
