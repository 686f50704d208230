#include "harness/interrupt.h"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <exception>

namespace svr {
namespace {

// Signal handlers may only touch lock-free atomics (and call async-signal-safe functions).
std::atomic<bool> g_interrupted{false};
std::atomic<bool> g_writing{false};

extern "C" void onInterrupt(int) {
  g_interrupted.store(true);
  if (!g_writing.load()) {
    static const char message[] = "\nsvr: interrupted\n";
    [[maybe_unused]] const auto n = ::write(STDERR_FILENO, message, sizeof(message) - 1);
    ::_exit(kInterruptedExitCode);
  }
}

}  // namespace

void installInterruptHandler() {
  struct sigaction action = {};
  action.sa_handler = onInterrupt;
  sigemptyset(&action.sa_mask);
  sigaction(SIGINT, &action, nullptr);
}

void throwIfInterrupted() {
  if (g_interrupted.load()) throw Interrupted();
}

WritingOutputs::WritingOutputs() { g_writing.store(true); }

WritingOutputs::~WritingOutputs() noexcept(false) {
  g_writing.store(false);
  // Do not throw while another exception unwinds the stack; that one is reported instead.
  if (std::uncaught_exceptions() == 0) throwIfInterrupted();
}

}  // namespace svr
