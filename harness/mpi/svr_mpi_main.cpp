// svr-mpi: `svr render` distributed over MPI ranks (design.md §5b, docs/distributed.md).
//   mpirun -np 4 svr-mpi render SCENE --out DIR [the options of svr render]
// Every rank reads only its brick of the volume, classifies and renders it; the k-channel
// images are composited in visibility order and rank 0 relights and writes what svr render
// writes, with each rank's brick, times and peak memory in render.json. A separate executable,
// so that svr itself never links MPI for the single-node user.
#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <mpi.h>

#include <exception>

#include "harness/command.h"
#include "harness/interrupt.h"
#include "harness/mpi/mpi_distribution.h"
#include "base/data_dir.h"
#include "base/error.h"

namespace {

// Parses and runs the render command on this rank; the exit status.
int run(int argc, char** argv, svr::MpiDistribution& distribution) {
  CLI::App app{"svr-mpi — svr render distributed over MPI ranks (one brick each)"};
  app.require_subcommand(1);
  svr::CommandContext context{svr::defaultDataDir()};
  context.distribution = &distribution;
  app.add_option("--data", context.data_dir, "data directory (spectra/, volumes/, scenes/)")
      ->capture_default_str();
  for (const auto& command : svr::commandEntries())
    if (command.name == "render")
      command.define(*app.add_subcommand(command.name, command.help), context);
  const bool talks = distribution.rank() == 0;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {  // every rank parses the same words: all stop alike
    return talks ? app.exit(e) : (e.get_exit_code() == 0 ? 0 : 2);
  } catch (const svr::AgreedFailure& e) {
    if (talks) fmt::print(stderr, "svr-mpi: error: {}\n", e.what());
    return 2;
  } catch (const svr::Interrupted&) {
    if (talks) fmt::print(stderr, "svr-mpi: interrupted\n");
    return svr::kInterruptedExitCode;
  } catch (const std::exception& e) {
    // Failed outside the phases the ranks agree on (while compositing or writing): the others
    // may be waiting on this rank, so the job is stopped rather than left hanging.
    fmt::print(stderr, "svr-mpi: error: rank {} of {}: {}\n", distribution.rank(),
               distribution.size(), e.what());
    MPI_Abort(MPI_COMM_WORLD, 2);
  }
  return context.status;
}

}  // namespace

int main(int argc, char** argv) {
  // Only the main thread calls MPI; OpenMP threads render within a rank.
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  int status = 0;
  {
    svr::MpiDistribution distribution(MPI_COMM_WORLD);
    status = run(argc, argv, distribution);
  }
  MPI_Finalize();
  return status;
}
