#pragma once
// SIGINT (Ctrl-C) for long commands: stop at once, with the exit status shells expect (130 =
// 128 + SIGINT) and a message, and never leave a partial file behind.
//
// While nothing is being written (loading, classifying, rendering) the handler ends the process
// straight away: there is nothing on disk to clean up, and backends need no cancellation points.
// Inside a WritingOutputs scope it only records the signal; the files are finished (each is
// written to a temporary name and renamed) and the command then exits 130 through
// throwIfInterrupted().

#include <stdexcept>

namespace svr {

inline constexpr int kInterruptedExitCode = 130;

// Thrown by throwIfInterrupted(); svr_main maps it to "svr: interrupted" and exit 130.
struct Interrupted : std::runtime_error {
  Interrupted() : std::runtime_error("interrupted") {}
};

void installInterruptHandler();
void throwIfInterrupted();

// Defers SIGINT to the end of the scope, then throws Interrupted if one arrived.
class WritingOutputs {
 public:
  WritingOutputs();
  ~WritingOutputs() noexcept(false);
  WritingOutputs(const WritingOutputs&) = delete;
  WritingOutputs& operator=(const WritingOutputs&) = delete;
};

}  // namespace svr
